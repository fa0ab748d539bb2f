#pragma once
// One exception type for every user-facing failure. The message names the
// file (and line or frame when known) and the reason; executables catch it at
// the top, print one line and exit non-zero.

#include <stdexcept>
#include <string>

namespace aar {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace aar
