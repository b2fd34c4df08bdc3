// Shared by the fuzz targets (docs/reliability.md, "Fuzzing").
//
// A target may throw pteromys::InputError for input it rejects: that is the
// clear message a user gets. Anything else (another exception, a crash, a
// sanitizer finding, a hang) is a bug, and fuzz_abort makes libFuzzer keep the
// input.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "pteromys/types.hpp"

namespace pteromys_fuzz {

[[noreturn]] inline void fuzz_abort(const std::string& why) {
  std::fprintf(stderr, "fuzz target: %s\n", why.c_str());
  std::abort();
}

/// Runs f; an InputError is an accepted answer, anything else aborts.
template <class F>
bool accepts(F&& f) {
  try {
    f();
    return true;
  } catch (const pteromys::InputError& e) {
    if (std::string(e.what()).empty()) fuzz_abort("InputError without a message");
    if (std::getenv("PTEROMYS_FUZZ_VERBOSE")) std::fprintf(stderr, "rejected: %s\n", e.what());
    return false;
  } catch (const std::exception& e) {
    fuzz_abort(std::string("unexpected exception (not an InputError): ") + e.what());
  } catch (...) {
    fuzz_abort("unexpected non-standard exception");
  }
}

}  // namespace pteromys_fuzz
