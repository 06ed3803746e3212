// The one translation unit that instantiates Catch2's runner; every test
// executable links it so that the runner is compiled once.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
