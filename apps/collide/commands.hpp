#pragma once
// Each subcommand of the `collide` tool lives in its own `<name>_command.cpp` and registers itself
// on the top-level CLI11 app through one of these functions (called from main.cpp).

#include <CLI/CLI.hpp>

namespace collide::cli {

/// `collide run [MAP|SCENE]`: a collision world stepped frame by frame, checked, summarised (run.hpp).
void register_run_command(CLI::App& app);

/// `collide query [FILE]`: JSON Lines questions in, answers out (spec/query-jsonl.md).
void register_query_command(CLI::App& app);

/// `collide cast [FILE]`: one shape cast answered and drawn (the motion, and the ray into A - B).
void register_cast_command(CLI::App& app);

/// `collide walk MESH.obj`: walk mesh of a level, agents wandering on it (walkmesh/).
void register_walk_command(CLI::App& app);

/// `collide sdf FILE`: signed distance field of a map, a scene or a mesh: built, measured, drawn,
/// sampled, particles bounced off it (sdf.hpp).
void register_sdf_command(CLI::App& app);

/// `collide decompose MESH.obj`: approximate convex decomposition of a triangle mesh into hulls,
/// written as an OBJ (--out) and drawn (--png), with the run's report (decompose/).
void register_decompose_command(CLI::App& app);

}  // namespace collide::cli
