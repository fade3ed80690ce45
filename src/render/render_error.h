// Failures of the renderer itself (no GL context, shader that does not compile,
// missing shader or font file). Bad scene values are tissu::InputError instead.
#pragma once

#include <stdexcept>

namespace tissu {

struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace tissu
