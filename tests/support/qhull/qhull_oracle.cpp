#include "qhull_oracle.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include <algorithm>
#include <cstdio>

namespace collide::test {
namespace {

// Runs qhull once with `options`; fills `out` through `read` while the hull is alive.
template <class Read>
bool run_qhull(std::span<const Vec3> points, const char* options, std::string& error,
               Read read) {
  std::vector<coordT> coords;
  coords.reserve(points.size() * 3);
  for (const Vec3& p : points) {
    coords.push_back(p.x);
    coords.push_back(p.y);
    coords.push_back(p.z);
  }
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, stderr);
  char* errbuf = nullptr;
  size_t errlen = 0;
  FILE* err = open_memstream(&errbuf, &errlen);
  std::string flags = options;
  const int code = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                flags.data(), nullptr, err);
  if (code == 0) read(qh);
  qh_freeqhull(qh, !qh_ALL);
  int curlong = 0;
  int totlong = 0;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::fclose(err);
  if (code != 0) error = errbuf ? errbuf : "qhull failed";
  std::free(errbuf);
  return code == 0;
}

}  // namespace

QhullResult qhull_hull(std::span<const Vec3> points) {
  QhullResult result;
  result.ok = run_qhull(points, "qhull", result.error, [&](qhT* qh) {
    qh_getarea(qh, qh->facet_list);
    result.volume = qh->totvol;
    vertexT* vertex;
    FORALLvertices { result.vertices.push_back(qh_pointid(qh, vertex->point)); }
    std::sort(result.vertices.begin(), result.vertices.end());
    facetT* facet;
    FORALLfacets {
      result.facets.push_back({{facet->normal[0], facet->normal[1], facet->normal[2]},
                               -facet->offset});
    }
  });
  if (result.ok) {
    std::string ignored;
    run_qhull(points, "qhull Qt", ignored, [&](qhT* qh) {
      facetT* facet;
      FORALLfacets { ++result.triangles; }
    });
  }
  return result;
}

}  // namespace collide::test
