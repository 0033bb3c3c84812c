// boost_test_pch.hpp — Boost.Test's heavy headers, precompiled once for every
// test program (tests/CMakeLists.txt; g++ Release builds).
//
// Everything <boost/test/unit_test.hpp> includes but the two parts that
// depend on the including file's BOOST_TEST_MODULE: unit_test_suite.hpp (the
// master suite's name) and unit_test.hpp itself (main()).  Each test defines
// BOOST_TEST_MODULE and includes <boost/test/unit_test.hpp> after this header
// (CMake includes it first), so those two are compiled per test with its
// module.  BOOST_TEST_MAIN is what detail/config.hpp derives from
// BOOST_TEST_MODULE; defined here, since config.hpp is read (once) here,
// before any test defines its module.
#pragma once
#define BOOST_TEST_MAIN
#include <boost/test/detail/config.hpp>
#include <boost/test/detail/pp_variadic.hpp>
#include <boost/test/framework.hpp>
#include <boost/test/test_tools.hpp>
#include <boost/test/tree/auto_registration.hpp>
#include <boost/test/tree/global_fixture.hpp>
#include <boost/test/tree/test_case_template.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>
