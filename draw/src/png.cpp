#include <collide/draw/png.hpp>

#include <collide/core/error.hpp>

#include <stb/stb_image_write.h>

namespace collide {

void write_png(const std::string& path, const Canvas& canvas) {
  const int ok = stbi_write_png(path.c_str(), canvas.width(), canvas.height(), 4, canvas.rgba().data(),
                                canvas.width() * 4);
  if (ok == 0) throw InvalidInput(path + ": cannot write PNG");
}

}  // namespace collide
