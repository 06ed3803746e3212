#include "garment/region_cut.h"

#include <algorithm>
#include <cstdint>
#include <deque>
#include <map>
#include <numeric>
#include <unordered_map>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/union_find.h"
#include "mesh/topology.h"

namespace gp {
namespace {

uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}
uint64_t directed_key(int a, int b) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
}

// Faces reached from `start` through edges that `blocked` does not stop.
template <class Blocked>
std::vector<char> flood_faces(const Eigen::MatrixXi& F, const Eigen::MatrixXi& TT, int start,
                              const Blocked& blocked) {
  std::vector<char> reached(static_cast<size_t>(F.rows()), 0);
  std::deque<int> queue{start};
  reached[start] = 1;
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int k = 0; k < 3; ++k) {
      const int g = TT(f, k);
      if (g < 0 || reached[g]) continue;
      if (blocked(edge_key(F(f, k), F(f, (k + 1) % 3)))) continue;
      reached[g] = 1;
      queue.push_back(g);
    }
  }
  return reached;
}


// A curve point: the zero of phi on body edge (u, v) at u + t (v - u).
struct Crossing {
  int u = -1, v = -1;
  double t = 0.0;
};

Eigen::Vector3d crossing_bary(const Eigen::MatrixXi& F, int face, const Crossing& x) {
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (F(face, k) == x.u) b[k] += 1.0 - x.t;
    if (F(face, k) == x.v) b[k] += x.t;
  }
  return b;
}

// Which loop each path vertex belongs to (-1 off the paths); loops must be
// disjoint, and the region point on none of them.
std::vector<int> loop_of_vertices(int n_vertices, const std::vector<LoopPath>& loops, int region_vertex,
                                  const std::string& region_where) {
  const int n_loops = static_cast<int>(loops.size());
  std::vector<int> vertex_loop(static_cast<size_t>(n_vertices), -1);
  for (int k = 0; k < n_loops; ++k) {
    for (int v : loops[k].vertex_ids) {
      if (vertex_loop[v] >= 0 && vertex_loop[v] != k)
        throw GeometryError("loops '" + loops[vertex_loop[v]].name + "' and '" + loops[k].name +
                                "' cross or touch at body vertex " + std::to_string(v),
                            loops[k].where);
      vertex_loop[v] = k;
    }
  }
  if (vertex_loop[region_vertex] >= 0)
    throw GeometryError("the region point lies on loop '" + loops[vertex_loop[region_vertex]].name +
                            "', so the region is empty; pick a point inside the garment",
                        region_where);
  return vertex_loop;
}

// The path edges: the loop of each, and the faces on either side of each.
struct PathEdges {
  std::unordered_map<uint64_t, int> loop;
  std::unordered_map<uint64_t, std::vector<int>> faces;
  // The two faces of edge i of loop k (loop k's vertices i, i + 1).
  const std::vector<int>& faces_of(const LoopPath& path, size_t i) {
    const auto& p = path.vertex_ids;
    return faces[edge_key(p[i], p[(i + 1) % p.size()])];
  }
};

// The path edges, each checked to have exactly two faces.
PathEdges path_edges(const Eigen::MatrixXi& F, const std::vector<LoopPath>& loops) {
  const int n_loops = static_cast<int>(loops.size());
  PathEdges edges;
  for (int k = 0; k < n_loops; ++k) {
    const auto& p = loops[k].vertex_ids;
    for (size_t i = 0; i < p.size(); ++i) edges.loop[edge_key(p[i], p[(i + 1) % p.size()])] = k;
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint64_t key = edge_key(F(f, k), F(f, (k + 1) % 3));
      if (edges.loop.count(key)) edges.faces[key].push_back(static_cast<int>(f));
    }
  for (int k = 0; k < n_loops; ++k) {
    const auto& p = loops[k].vertex_ids;
    for (size_t i = 0; i < p.size(); ++i) {
      const auto& faces = edges.faces_of(loops[k], i);
      if (faces.size() != 2)
        throw GeometryError("loop '" + loops[k].name + "' runs along body edge " +
                                std::to_string(p[i]) + "-" + std::to_string(p[(i + 1) % p.size()]) +
                                " which has " + std::to_string(faces.size()) +
                                " faces (the body must be manifold and closed along the loops)",
                            loops[k].where);
    }
  }
  return edges;
}

// The faces of the region: the flood fill from the region point's first face
// that crosses no path. Throws where a loop leaks (with only that loop as a
// barrier, the fill reaches both faces of one of its edges) or does not
// border the region.
std::vector<char> region_faces(const Eigen::MatrixXi& F, int n_vertices, const std::vector<LoopPath>& loops,
                               PathEdges& edges, int region_vertex, const std::string& region_where) {
  const int n_loops = static_cast<int>(loops.size());
  const Eigen::MatrixXi TT = triangle_adjacency(F);
  const auto vf = vertex_faces(F, n_vertices);
  if (vf[region_vertex].empty())
    throw GeometryError("the region point is a body vertex without faces", region_where);
  const int start_face = vf[region_vertex].front();

  for (int k = 0; k < n_loops; ++k) {
    const auto reached = flood_faces(F, TT, start_face, [&](uint64_t key) {
      const auto it = edges.loop.find(key);
      return it != edges.loop.end() && it->second == k;
    });
    for (size_t i = 0; i < loops[k].vertex_ids.size(); ++i) {
      const auto& faces = edges.faces_of(loops[k], i);
      if (reached[faces[0]] && reached[faces[1]])
        throw GeometryError("loop '" + loops[k].name +
                                "' does not separate the region from the rest of the body: the "
                                "region leaks around it",
                            loops[k].where);
    }
  }

  auto region = flood_faces(F, TT, start_face, [&](uint64_t key) { return edges.loop.count(key) > 0; });
  std::vector<char> bounds(static_cast<size_t>(n_loops), 0);
  for (int k = 0; k < n_loops; ++k) {
    for (size_t i = 0; i < loops[k].vertex_ids.size() && !bounds[k]; ++i) {
      const auto& faces = edges.faces_of(loops[k], i);
      if (region[faces[0]] != region[faces[1]]) bounds[k] = 1;
    }
  }
  if (std::none_of(bounds.begin(), bounds.end(), [](char b) { return b != 0; }))
    throw GeometryError("the region point lies outside every loop", region_where);
  for (int k = 0; k < n_loops; ++k)
    if (!bounds[k])
      throw GeometryError("the region point lies outside loop '" + loops[k].name +
                              "' (that loop does not border the region)",
                          region_where);
  return region;
}

// The side indicator phi: +1 in the region, -1 outside, 0 on the paths; and
// which vertices the region held before smoothing.
struct Side {
  Eigen::VectorXd phi;
  std::vector<char> initially_inside;
};

Side side_indicator(const Eigen::MatrixXi& F, int n_vertices, const std::vector<char>& region,
                    const std::vector<int>& vertex_loop) {
  Side side{Eigen::VectorXd::Constant(n_vertices, -1.0), std::vector<char>(static_cast<size_t>(n_vertices), 0)};
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (region[f])
      for (int k = 0; k < 3; ++k) {
        side.phi[F(f, k)] = 1.0;
        side.initially_inside[F(f, k)] = 1;
      }
  for (int v = 0; v < n_vertices; ++v)
    if (vertex_loop[v] >= 0) {
      side.phi[v] = 0.0;
      side.initially_inside[v] = 0;
    }
  return side;
}

// The band of rings around the paths, with the nearest loop of each vertex
// (-1 outside the band).
struct Band {
  std::vector<int> ids;           // band vertices, ascending
  std::vector<int> nearest_loop;  // per body vertex
};

Band band_around_loops(int n_vertices, const std::vector<std::vector<int>>& neighbors,
                       const std::vector<LoopPath>& loops, int band_rings) {
  const int n_loops = static_cast<int>(loops.size());
  std::vector<int> ring(static_cast<size_t>(n_vertices), -1);
  Band band;
  band.nearest_loop.assign(static_cast<size_t>(n_vertices), -1);
  std::deque<int> queue;
  for (int k = 0; k < n_loops; ++k)
    for (int v : loops[k].vertex_ids) {
      ring[v] = 0;
      band.nearest_loop[v] = k;
      queue.push_back(v);
    }
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop_front();
    if (ring[v] >= band_rings) continue;
    for (int w : neighbors[v])
      if (ring[w] < 0) {
        ring[w] = ring[v] + 1;
        band.nearest_loop[w] = band.nearest_loop[v];
        queue.push_back(w);
      }
  }
  for (int v = 0; v < n_vertices; ++v)
    if (ring[v] >= 0) band.ids.push_back(v);
  return band;
}

// Jacobi diffusion of phi in the band: a discrete heat flow whose level sets
// move by their curvature, straightening the zig-zag of the edge path. Then
// |phi| is kept off zero so that no curve point falls on a body vertex.
void smooth_in_band(Eigen::VectorXd& phi, const std::vector<int>& band_ids,
                    const std::vector<std::vector<int>>& neighbors, const RegionCutOptions& options) {
  Eigen::VectorXd next = phi;
  for (int it = 0; it < options.smoothing_iterations; ++it) {
    for (int v : band_ids) {
      if (neighbors[v].empty()) continue;
      double mean = 0.0;
      for (int w : neighbors[v]) mean += phi[w];
      mean /= static_cast<double>(neighbors[v].size());
      next[v] = 0.5 * phi[v] + 0.5 * mean;
    }
    phi = next;
  }
  for (int v : band_ids)
    if (std::abs(phi[v]) < options.min_level) phi[v] = phi[v] < 0 ? -options.min_level : options.min_level;
}

// The vertices inside: the positive part of phi holding most of the original region.
std::vector<char> inside_vertices(const Side& side, const std::vector<std::vector<int>>& neighbors,
                                  const std::string& region_where) {
  const Eigen::VectorXd& phi = side.phi;
  const int n_vertices = static_cast<int>(phi.size());
  UnionFind sets(static_cast<size_t>(n_vertices));
  for (int v = 0; v < n_vertices; ++v)
    if (phi[v] > 0)
      for (int w : neighbors[v])
        if (phi[w] > 0) sets.unite(v, w);
  std::map<int, int> votes;
  for (int v = 0; v < n_vertices; ++v)
    if (phi[v] > 0 && side.initially_inside[v]) ++votes[sets.find(v)];
  if (votes.empty()) throw GeometryError("the region is empty after smoothing its loops", region_where);
  int component = votes.begin()->first, best = votes.begin()->second;
  for (const auto& [root, count] : votes)
    if (count > best) {
      component = root;
      best = count;
    }
  std::vector<char> inside(static_cast<size_t>(n_vertices), 0);
  for (int v = 0; v < n_vertices; ++v) inside[v] = phi[v] > 0 && sets.find(v) == component;
  return inside;
}

// The region mesh cut along phi's zero level: inside vertices, then curve
// points in order of creation, with the body face of every region face.
struct CutMesh {
  std::vector<Crossing> crossing_of;  // per region vertex (u = -1 for body vertices)
  std::vector<int> face_body;         // per region face
};

CutMesh cut_along_level(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const Eigen::VectorXd& phi,
                        const std::vector<char>& inside, RegionCut& cut) {
  const int n_vertices = static_cast<int>(V.rows());
  CutMesh mesh;
  std::vector<int> region_id(static_cast<size_t>(n_vertices), -1);
  std::vector<Eigen::Vector3d> points;
  std::vector<Crossing>& crossing_of = mesh.crossing_of;
  for (int v = 0; v < n_vertices; ++v)
    if (inside[v]) {
      region_id[v] = static_cast<int>(points.size());
      points.push_back(V.row(v).transpose());
      crossing_of.push_back({});
    }
  std::unordered_map<uint64_t, int> crossing_id;
  auto crossing = [&](int u, int v) {  // u inside, v outside
    const uint64_t key = edge_key(u, v);
    const auto it = crossing_id.find(key);
    if (it != crossing_id.end()) return it->second;
    Crossing x{u, v, phi[u] / (phi[u] - phi[v])};
    const int id = static_cast<int>(points.size());
    points.push_back((1.0 - x.t) * V.row(u).transpose() + x.t * V.row(v).transpose());
    crossing_of.push_back(x);
    crossing_id[key] = id;
    return id;
  };
  std::vector<Eigen::Vector3i> faces;
  std::vector<int>& face_body = mesh.face_body;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    int count = 0;
    for (int k = 0; k < 3; ++k) count += inside[F(f, k)];
    if (count == 0) continue;
    if (count == 3) {
      faces.push_back({region_id[F(f, 0)], region_id[F(f, 1)], region_id[F(f, 2)]});
      face_body.push_back(static_cast<int>(f));
      continue;
    }
    // Rotate the corners so that the lone vertex (inside for one, outside for
    // two) comes first or last, keeping the orientation.
    int r = 0;
    for (int k = 0; k < 3; ++k)
      if ((count == 1 && inside[F(f, k)]) || (count == 2 && !inside[F(f, k)])) r = k;
    if (count == 1) {
      const int a = F(f, r), b = F(f, (r + 1) % 3), c = F(f, (r + 2) % 3);
      faces.push_back({region_id[a], crossing(a, b), crossing(a, c)});
      face_body.push_back(static_cast<int>(f));
    } else {
      const int c = F(f, r), a = F(f, (r + 1) % 3), b = F(f, (r + 2) % 3);
      const int ia = region_id[a], ib = region_id[b], xb = crossing(b, c), xa = crossing(a, c);
      // Split the quad a, b, xb, xa along its shorter diagonal.
      if ((points[ia] - points[xb]).squaredNorm() <= (points[ib] - points[xa]).squaredNorm()) {
        faces.push_back({ia, ib, xb});
        faces.push_back({ia, xb, xa});
      } else {
        faces.push_back({ia, ib, xa});
        faces.push_back({ib, xb, xa});
      }
      face_body.push_back(static_cast<int>(f));
      face_body.push_back(static_cast<int>(f));
    }
  }

  cut.V.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t i = 0; i < points.size(); ++i) cut.V.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  cut.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t i = 0; i < faces.size(); ++i) cut.F.row(static_cast<Eigen::Index>(i)) = faces[i].transpose();
  for (Eigen::Index f = 0; f < cut.F.rows(); ++f) {
    const Eigen::Vector3d a = cut.V.row(cut.F(f, 0)), b = cut.V.row(cut.F(f, 1)), c = cut.V.row(cut.F(f, 2));
    cut.area += 0.5 * (b - a).cross(c - a).norm();
  }
  return mesh;
}

// Each boundary of the region mesh as the curve of the loop nearest to most
// of its points, segment by segment in the body faces it crosses.
void trace_curves(const Eigen::MatrixXi& F, const std::vector<LoopPath>& loops, const CutMesh& mesh,
                  const std::vector<int>& nearest_loop, const std::string& region_where, RegionCut& cut) {
  const int n_loops = static_cast<int>(loops.size());
  std::unordered_map<uint64_t, int> directed_face;
  for (Eigen::Index f = 0; f < cut.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      directed_face[directed_key(cut.F(f, k), cut.F(f, (k + 1) % 3))] = static_cast<int>(f);

  cut.curves.assign(static_cast<size_t>(n_loops), {});
  cut.boundary_vertex_ids.assign(static_cast<size_t>(n_loops), {});
  for (const auto& boundary : boundary_loops(cut.F)) {
    std::vector<int> count(static_cast<size_t>(n_loops), 0);
    for (int x : boundary) {
      if (mesh.crossing_of[x].u < 0)
        throw GeometryError("the region reaches an open border of the body mesh; the loops must "
                            "enclose it",
                            region_where);
      ++count[nearest_loop[mesh.crossing_of[x].u]];
    }
    const int k = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
    if (!cut.boundary_vertex_ids[k].empty())
      throw GeometryError("smoothing split loop '" + loops[k].name +
                              "' into several curves; move it away from the other loops or "
                              "give it more points",
                          loops[k].where);
    cut.boundary_vertex_ids[k] = boundary;
    BodyCurve& curve = cut.curves[k];
    curve.name = loops[k].name;
    for (size_t i = 0; i < boundary.size(); ++i) {
      const int a = boundary[i], b = boundary[(i + 1) % boundary.size()];
      const int body_face = mesh.face_body[directed_face.at(directed_key(a, b))];
      curve.segments.push_back({body_face, crossing_bary(F, body_face, mesh.crossing_of[a]),
                                crossing_bary(F, body_face, mesh.crossing_of[b])});
    }
  }
  for (int k = 0; k < n_loops; ++k)
    if (cut.boundary_vertex_ids[k].empty())
      throw GeometryError("loop '" + loops[k].name +
                              "' vanished when smoothed (it encloses too little of the body)",
                          loops[k].where);
}

}  // namespace

Eigen::MatrixXd evaluate_curve(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                               const BodyCurve& curve) {
  Eigen::MatrixXd P(static_cast<Eigen::Index>(curve.segments.size()), 3);
  for (size_t i = 0; i < curve.segments.size(); ++i) {
    const SurfacePoint p{curve.segments[i].face, curve.segments[i].bary_start};
    P.row(static_cast<Eigen::Index>(i)) = evaluate(V, F, p).transpose();
  }
  return P;
}

double curve_length(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F, const BodyCurve& curve) {
  const Eigen::MatrixXd P = evaluate_curve(V, F, curve);
  double length = 0.0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) length += (P.row((i + 1) % P.rows()) - P.row(i)).norm();
  return length;
}

RegionCut cut_region(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const std::vector<LoopPath>& loops, int region_vertex,
                     const std::string& region_where, const RegionCutOptions& options) {
  const int n_vertices = static_cast<int>(V.rows());
  if (loops.empty()) throw SpecError("a garment needs at least one boundary loop", region_where);
  const std::vector<int> vertex_loop = loop_of_vertices(n_vertices, loops, region_vertex, region_where);
  PathEdges edges = path_edges(F, loops);
  const std::vector<char> region = region_faces(F, n_vertices, loops, edges, region_vertex, region_where);
  Side side = side_indicator(F, n_vertices, region, vertex_loop);
  const auto neighbors = vertex_neighbors(F, n_vertices);
  const Band band = band_around_loops(n_vertices, neighbors, loops, options.band_rings);
  smooth_in_band(side.phi, band.ids, neighbors, options);
  const std::vector<char> inside = inside_vertices(side, neighbors, region_where);

  RegionCut cut;
  const CutMesh mesh = cut_along_level(V, F, side.phi, inside, cut);
  if (cut.F.rows() < 4 || !(cut.area > 0))
    throw GeometryError("the region is empty or degenerate (" + std::to_string(cut.F.rows()) +
                            " triangles after cutting)",
                        region_where);
  trace_curves(F, loops, mesh, band.nearest_loop, region_where, cut);
  return cut;
}

}  // namespace gp
