#pragma once
/// @file
/// PNG files of canvases (through stb_image_write).

#include <collide/draw/canvas.hpp>

#include <string>

namespace collide {

/// Writes `canvas` as an 8-bit RGBA PNG. Throws InvalidInput naming the path when it cannot be
/// written.
void write_png(const std::string& path, const Canvas& canvas);

}  // namespace collide
