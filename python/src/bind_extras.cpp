// Python bindings of the capabilities beyond the foundation. Each section binds one topic header.

#include "common.h"

namespace geotex::python {

void bind_extras(py::module_& m) {}

}  // namespace geotex::python
