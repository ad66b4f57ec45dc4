#pragma once
/// @file
/// Pictures of a signed distance field over a plane (a 2D field, or a slice of a 3D one): the
/// distance colour-mapped (inside blue, outside orange, paler with the distance), iso-lines
/// every few voxels, the zero contour (the surface) in a strong colour, a title, a scale bar and
/// a legend. The values come as a grid of samples, so any field (dense, sparse, a slice) draws
/// the same way; this header does not depend on the field types.

#include <collide/core/aabb.hpp>
#include <collide/draw/palette.hpp>

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace collide {

/// Inside the solid (negative distances), at the surface.
inline constexpr Color kFieldInside{40, 110, 200, 255};
/// Outside the solid (positive distances), at the surface.
inline constexpr Color kFieldOutside{235, 130, 30, 255};
/// Far from the surface either way, the colours fade towards this.
inline constexpr Color kFieldFar{250, 248, 240, 255};
/// The zero contour: the surface.
inline constexpr Color kFieldZeroContour{10, 10, 10, 255};
/// The iso-lines at multiples of the spacing.
inline constexpr Color kFieldIsoLine{30, 30, 30, 90};
/// Iso-lines every this many voxels unless FieldPictureOptions::iso_spacing says otherwise.
inline constexpr float kFieldIsoSpacingVoxels = 4.0f;

/// Samples of a signed distance field on a regular grid of a plane: sample (i, j) lies at
/// origin + (i, j) * spacing and holds values[j * width + i] (i along the picture's horizontal
/// axis, j along its vertical one); negative inside. Not owned.
struct FieldSlice {
  std::span<const float> values;  ///< width * height samples, row by row
  int width = 0;                  ///< samples per row, >= 2
  int height = 0;                 ///< rows, >= 2
  float spacing = 1.0f;           ///< distance between neighbouring samples, world units, > 0
  Vec2 origin{0.0f};              ///< world position (in the plane) of sample (0, 0)
};

/// How a field picture is drawn.
struct FieldPictureOptions {
  std::string title;                 ///< first line above the plot (empty: none)
  int size = 1024;                   ///< the plot's longer side, pixels, [16, kMaxPictureSide]
  /// World units between iso-lines; 0: kFieldIsoSpacingVoxels samples' spacing.
  float iso_spacing = 0.0f;
  /// True: row 0 at the top, the vertical axis pointing down (a Tiled map, a top-down view);
  /// false: row 0 at the bottom, the vertical axis up.
  bool vertical_down = false;
  std::string horizontal_axis = "x";  ///< axis names for the scale line ("x", "z")
  std::string vertical_axis = "y";
  std::string unit = "units";         ///< the world unit's name in the scale bar ("px", "m")
};

/// Where things are in a picture written by `save_field_picture`, pixels (x right, y down from
/// the top-left corner).
struct FieldPictureSize {
  int width = 0;        ///< the whole picture
  int height = 0;
  int plot_left = 0;    ///< the plot: slice sample (0, 0) at its bottom-left corner (top-left
  int plot_top = 0;     ///< with vertical_down), the last sample at the opposite corner
  int plot_width = 0;
  int plot_height = 0;
};

/// The segments of the contour where the bilinear interpolation of `slice` crosses `level`
/// (world units, in the plane), by marching squares (Lorensen & Cline's marching cubes in 2D):
/// each cell's crossings on its edges by linear interpolation, a saddle cell resolved by the
/// value at its centre. A sample exactly at `level` counts as above it. Throws InvalidInput for
/// a slice whose sizes do not match its values.
[[nodiscard]] std::vector<std::array<Vec2, 2>> contour_segments(const FieldSlice& slice, float level);

/// Writes a PNG of `slice` to `path`: the plot (the slice's extent scaled to options.size on its
/// longer side; each pixel the bilinear value at its centre, colour-mapped), iso-lines every
/// iso_spacing, the zero contour, the title above, and below a scale bar (a round length) and a
/// legend (inside, outside, surface, iso-lines with their spacing). Returns the picture's size.
/// Throws InvalidInput for a bad slice or size and when the file cannot be written (naming it),
/// std::bad_alloc when Cairo runs out of memory.
FieldPictureSize save_field_picture(const FieldSlice& slice, const FieldPictureOptions& options,
                                    const std::filesystem::path& path);

}  // namespace collide
