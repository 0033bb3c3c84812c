#!/usr/bin/env bash
# progress_on_terminal: the long proofs show progress on a terminal and
# nothing elsewhere (prover/include/warpmesh/key_progress.hpp).
#
#   progress_on_terminal.sh WARPMESH-PROVE-BCC WARPMESH
#
# Runs warpmesh-prove-bcc and `warpmesh prove` on a few keys under a
# pseudo-terminal (script(1), util-linux) and with stderr to a file: on the
# terminal stderr carries "<done> of <total> keys" lines; in the file only the
# summary; the certificates are byte-identical either way.
set -euo pipefail
prove_bcc="$1" warpmesh="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "progress_on_terminal: $*" >&2; exit 1; }
keys="$(seq -s, 0 250 2000)"  # 9 keys (the sanitizer build runs this too)
script -qec "'$prove_bcc' --threads 1 --keys $keys --out '$tmp/tty.cert'" /dev/null </dev/null >"$tmp/tty.log"
"$prove_bcc" --threads 1 --keys "$keys" --out "$tmp/file.cert" 2>"$tmp/file.log" </dev/null
grep -q "warpmesh-prove-bcc: proving: [0-9]* of 9 keys" "$tmp/tty.log" || fail "no progress from warpmesh-prove-bcc on a terminal"
grep -q " of 9 keys" "$tmp/file.log" && fail "warpmesh-prove-bcc wrote progress to a file"
grep -q "9 keys, 0 not proved" "$tmp/file.log" || fail "warpmesh-prove-bcc's summary is missing"
cmp -s "$tmp/tty.cert" "$tmp/file.cert" || fail "warpmesh-prove-bcc's certificate depends on the terminal"

mkdir "$tmp/tty" "$tmp/file"
script -qec "'$warpmesh' prove --rule maxmin --keys $keys --threads 1 --out '$tmp/tty'" /dev/null </dev/null >"$tmp/tty2.log"
"$warpmesh" prove --rule maxmin --keys "$keys" --threads 1 --out "$tmp/file" 2>"$tmp/file2.log" >/dev/null </dev/null
grep -q "warpmesh prove: maxmin: proving: [0-9]* of 9 keys" "$tmp/tty2.log" || fail "no progress from warpmesh prove on a terminal"
grep -q " of 9 keys" "$tmp/file2.log" && fail "warpmesh prove wrote progress to a file"
cmp -s "$tmp/tty/maxmin.cert" "$tmp/file/maxmin.cert" || fail "warpmesh prove's certificate depends on the terminal"
echo "progress_on_terminal: ok"
