// Bad input: a file or value that cannot be used as it is. The message names the file and
// the line or key. Commands turn it into exit code 2. Lives in core (no dependencies) so
// that every library that reads files (trainer, identify) throws the same type.
#pragma once

#include <stdexcept>

namespace colosim {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace colosim
