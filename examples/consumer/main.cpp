// Links against collide and uses a shape constructor: proves headers, library and glm resolve.
#include <collide/shape/polygon.hpp>

int main() {
  const collide::Polygon box = collide::make_box({1.0f, 2.0f});
  return box.count == 4 ? 0 : 1;
}
