// demlab::Error: the one exception type of the core. It carries a human message in the
// standard Tcl wording and a machine-readable error code (a list whose first word is DEMLAB),
// so the Tcl layer can turn it into a Tcl error with -errorcode unchanged.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace demlab {

class Error : public std::runtime_error {
 public:
  // code: the words after DEMLAB, for example {"VALUE", "BOX"}.
  Error(std::string message, std::vector<std::string> code)
      : std::runtime_error(std::move(message)), code_(std::move(code)) {
    code_.insert(code_.begin(), "DEMLAB");
  }

  // Returns the full error code, starting with "DEMLAB".
  const std::vector<std::string>& code() const noexcept { return code_; }

  // Returns this error with " (context)" after its message and the same code: a file reader's
  // `(file "x" line 3)`.
  Error within(const std::string& context) const {
    Error e = *this;
    static_cast<std::runtime_error&>(e) = std::runtime_error(std::string(what()) + " (" + context + ")");
    return e;
  }

 private:
  std::vector<std::string> code_;
};

}  // namespace demlab
