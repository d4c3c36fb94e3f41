#pragma once
// Geometry of a closed triangulated surface: areas, normals, enclosed volume, centroid
// and second moment of the enclosed volume (through the divergence theorem,
// docs/conventions.md).
#include "common/vec3.hpp"
#include "mesh/icosphere.hpp"

#include <vector>

namespace capsim {

// Twice-area vector (x1 - x0) x (x2 - x0): its length is 2 A, its direction the normal.
CAPSIM_HD Vec3 area_vector2(Vec3 x0, Vec3 x1, Vec3 x2) {
  return cross(x1 - x0, x2 - x0);
}

double surface_area(const Topology& topo, const Vec3* x);
double enclosed_volume(const Topology& topo, const Vec3* x);
Vec3 volume_centroid(const Topology& topo, const Vec3* x);

// Mo = int_V (x - c)(x - c) dV about the volume centroid c.
Mat3 second_moment(const Topology& topo, const Vec3* x, Vec3 centroid);

// Lumped node areas: each triangle gives a third of its area to each of its nodes.
std::vector<double> node_areas(const Topology& topo, const Vec3* x);

// Each node's sum of its triangles' twice-area vectors (area_vector2): 6 dV/dx_i, the
// gradient of the enclosed volume, and the direction of the node normal.
std::vector<Vec3> node_area_vectors(const Topology& topo, const Vec3* x);

// Unit node normals, the area-weighted average of the adjacent triangles' normals.
std::vector<Vec3> node_normals(const Topology& topo, const Vec3* x);

double mean_edge_length(const Topology& topo, const Vec3* x);

} // namespace capsim
