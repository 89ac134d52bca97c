#ifndef FREESTAND_INPUT_ERROR_H
#define FREESTAND_INPUT_ERROR_H

#include <stdexcept>
#include <string>

namespace freestand {

// Bad user input (a file, a line, a parameter). The message names where the
// problem is, e.g. "DUZCE.AT2:7: non-numeric token 'abc'", so it can be shown
// to the user as it is.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws InputError "where: what" (where: a file, "file: field", ...).
[[noreturn]] inline void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

}  // namespace freestand

#endif
