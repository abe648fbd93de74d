// softpbr/loaders/load_error.h — the error of every model loader (OBJ, glTF): a file could
// not be loaded.
#pragma once

#include <stdexcept>

namespace softpbr::pbr {

// A file could not be loaded; what() names the file (and line when known) and says what was
// expected.
class LoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace softpbr::pbr
