// The stack behind skypol.Stack: a stack::Stack that owns every pixel. NumPy arrays handed to
// Python are views of its frames' channel vectors (python/convert.h, channel_view), kept alive by
// the Python object that holds this; nothing here resizes a channel once a stack is built, so the
// views stay valid. Estimators read the same memory: what a user edits in the arrays is what they
// estimate on.
#pragma once

#include <string>

#include "stack/frame.h"

namespace skypol::python {

struct PyStack {
  stack::Stack stack;
  std::string sky_model = "unknown";  // for a written header: the renderer's sky, or the read file's
};

}  // namespace skypol::python
