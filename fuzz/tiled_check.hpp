#pragma once
// What must hold for any bytes given to the Tiled loader as a map, an external tileset or a
// template (fuzz_tiled_*, and the regression test that replays what the fuzzers found): shared
// so both check the same. load_tiled_map reads files, so the input is written into a scratch
// folder next to small fixed files it may refer to (t.tsx, a.tx), or that refer to it (host_*.tmx).

#include "fuzz_check.hpp"

#include <collide/core/error.hpp>
#include <collide/io/tiled.hpp>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <set>
#include <string>
#include <string_view>

namespace collide::fuzz {

/// Which file the fuzzed bytes are.
enum class TiledInput {
  tmx,      ///< the map, map.tmx
  tmj,      ///< the map, map.tmj
  tileset,  ///< the external tileset of a fixed map (host_*.tmx): f.tsj if it starts with '{', else f.tsx
  templ,    ///< an object template of a fixed map (host_*.tmx): f.tj if it starts with '{', else f.tx
};

/// "" when `input`, as the file `kind` says, is handled as docs/limits.md promises, else what
/// went wrong:
///  - load_tiled_map throws nothing but InvalidInput, whose message names the map file first and
///    is valid UTF-8;
///  - a map it accepts has colliders whose transforms and bounding boxes are finite.
/// Crashes, hangs and undefined behaviour are the sanitizers' and libFuzzer's to catch.
/// `dir` is a scratch folder (created if missing; its files are overwritten). `accepted`, if
/// given, is set to whether the map loaded.
inline std::string check_tiled(TiledInput kind, std::string_view input, const std::filesystem::path& dir,
                               bool* accepted = nullptr) {
  if (accepted != nullptr) *accepted = false;
  namespace fs = std::filesystem;
  const bool json = !input.empty() && input.front() == '{';
  // The fixed files: a tileset with a collision tile (t.tsx), a template (a.tx), and hosts that
  // use both, one per kind of fuzzed tileset or template (f.*). The fuzzed bytes never overwrite
  // a fixed file, so each fixed file is written once per process and folder: rewriting (and
  // truncating) three files per execution made file-system work most of a run's time.
  static const std::string kTileset = R"(<tileset name="t" tilewidth="16" tileheight="16" tilecount="4" columns="2">
 <tile id="1"><objectgroup><object id="1" x="2" y="2" width="8" height="4"/><object id="2" x="0" y="8"><polygon points="0,0 16,0 8,8"/></object></objectgroup></tile>
 <tile id="2"><objectgroup><object id="1" x="4" y="4" width="8" height="8"><ellipse/></object></objectgroup></tile>
</tileset>)";
  static const std::string kTemplate =
      R"(<template><tileset firstgid="1" source="t.tsx"/><object name="door" gid="2" width="32" height="32"/></template>)";
  static std::set<fs::path> written;
  const auto write_fixed = [&](const fs::path& path, const std::string& bytes) {
    if (written.insert(path).second) write_file(path, bytes);
  };
  fs::create_directories(dir);
  write_fixed(dir / "t.tsx", kTileset);
  write_fixed(dir / "a.tx", kTemplate);
  const auto host = [&](const std::string& tileset_name, const std::string& template_name) {
    // Named by both files in full: a tileset kind's host (f.tsx, a.tx) and a template kind's
    // (t.tsx, f.tx) must not share a name when one process checks both, as the regression test does.
    const auto part = [](const std::string& name) {
      std::string s = name;
      std::replace(s.begin(), s.end(), '.', '_');
      return s;
    };
    const fs::path path = dir / ("host_" + part(tileset_name) + "_" + part(template_name) + ".tmx");
    write_fixed(path, R"(<map version="1.10" orientation="orthogonal" width="4" height="2" tilewidth="16" tileheight="16">
 <tileset firstgid="1" source=")" + tileset_name + R"("/>
 <layer name="cells" width="4" height="2"><data encoding="csv">1,2,3,4,4,3,2,1</data></layer>
 <objectgroup name="things"><object id="1" gid="2" x="10" y="40" width="16" height="16" rotation="30"/>
  <object id="2" template=")" + template_name + R"(" x="50" y="60"/></objectgroup>
</map>)");
    return path;
  };
  fs::path map;
  switch (kind) {
    case TiledInput::tmx: map = dir / "map.tmx"; write_file(map, input); break;
    case TiledInput::tmj: map = dir / "map.tmj"; write_file(map, input); break;
    case TiledInput::tileset: {
      const std::string fuzzed = json ? "f.tsj" : "f.tsx";
      map = host(fuzzed, "a.tx");
      write_file(dir / fuzzed, input);
      break;
    }
    case TiledInput::templ: {
      const std::string fuzzed = json ? "f.tj" : "f.tx";
      map = host("t.tsx", fuzzed);
      write_file(dir / fuzzed, input);
      break;
    }
  }
  TiledMap loaded;
  try {
    loaded = load_tiled_map(map);
  } catch (const InvalidInput& e) {
    return check_message(e.what(), map.generic_string() + ": ");
  } catch (const std::exception& e) {
    return std::string("load_tiled_map threw other than InvalidInput: ") + e.what();
  }
  if (accepted != nullptr) *accepted = true;
  for (const TiledCollider& c : loaded.colliders) {
    if (!is_valid(c.transform) || !is_valid(compute_aabb(c.shape, c.transform))) {
      return "an accepted map has a collider that is not finite (layer '" + c.source.layer + "', object " +
             std::to_string(c.source.object_id) + ")";
    }
  }
  return {};
}

}  // namespace collide::fuzz
