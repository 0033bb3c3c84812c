// Standalone entry point of the prover: `warpmesh-prove [--out DIR] [--threads N]`.
#include "warpmesh/prove.hpp"

int main(int argc, char** argv) { return warpmesh::prove_main(argc, argv); }
