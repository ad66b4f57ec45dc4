#pragma once
/// @file
/// Points as text, one per line: "x y" (2D) or "x y z" (3D), world units, numbers separated by
/// spaces or tabs (the input of `collide sdf --sample`). Blank lines and lines whose first
/// non-blank character is '#' are skipped; lines end at "\n", "\r\n" or "\r". Every number must
/// be a finite float ("1", "-2.5", "+3e-2"; not "nan", "inf" or 1e39). The point count is bounded
/// by the file's size (kMaxInputFileBytes, 64 MiB).

#include <collide/core/aabb.hpp>  // VecN

#include <filesystem>
#include <string_view>
#include <vector>

namespace collide::io {

/// The points of `text`, `D` numbers per line (D = 2 or 3), in order. `name` stands for the file
/// in error messages. Throws InvalidInput "NAME:LINE: ..." naming the line (counted from 1, blank
/// and comment lines included) for a line of another count of numbers ("points.txt:3: expected
/// 3 numbers (x y z), found 2"), a word that is not a number ("points.txt:4: y 'abc' is not a
/// number"), one that is not finite ("... z 'nan' is not finite") or beyond float range ("... x
/// '1e39' is out of float range"). An empty list is no error.
template <int D>
[[nodiscard]] std::vector<VecN<D>> parse_points(std::string_view text, const std::filesystem::path& name);

/// `parse_points` on the file at `path` (its name as given in the messages). Throws InvalidInput
/// "PATH: cannot be read" for a file that is missing, a folder or unreadable, "PATH: larger than
/// N bytes (the limit, kMaxInputFileBytes)", and what parse_points throws.
template <int D>
[[nodiscard]] std::vector<VecN<D>> load_points(const std::filesystem::path& path);

}  // namespace collide::io
