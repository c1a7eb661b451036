// Built against an installed geotex by the install_and_find_package test.
#include <geotex/core/geometry.h>
#include <geotex/tools/shapes.h>

int main() {
  const geotex::Mesh m = geotex::icosphere(1);
  return geotex::euler_characteristic(m) == 2 ? 0 : 1;
}
