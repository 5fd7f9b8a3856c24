// A mesh's triangles as POV-Ray 3.7 keeps and intersects them (source/backend/shape/mesh.cpp,
// parser/parse.cpp's Parse_Mesh), so that their hit depths, hit points and normals, and so
// their pixels, are POV-Ray's bit for bit (docs/fidelity.md). Unlike a lone triangle, a mesh
// stays in its own space: its transforms are composed into one TRANSFORM (core/pov_transform.h)
// and each ray is carried into mesh space, its direction made unit there. What a triangle
// keeps is what POV-Ray keeps, in single precision: its corners, its face normal and the
// plane's distance, and for a smooth one its vertex normals and the vector that gives its
// interpolation weight; all of it is worked out in double from the corners as written and
// rounded where POV-Ray stores it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/ray.h"
#include "core/vec3.h"

namespace pvrt {

// One triangle of a mesh, in mesh space (MESH_TRIANGLE with its vertex and normal arrays'
// values in place): p1 and p2 as Compute_Mesh_Triangle leaves them (possibly swapped).
struct PovMeshTriangleShape {
  float p[3][3] = {};      // corners
  float normal[3] = {};    // the unit face normal, rounded to float
  float distance = 0;      // the plane normal.X + distance = 0, rounded to float
  uint8_t axis = kNever;   // the face normal's largest axis: the edges are tested across the other two
  static constexpr uint8_t kNever = 3;  // never hit: left out by POV-Ray's parser (corners on a line)

  Vec3 corner(int i) const { return {p[i][0], p[i][1], p[i][2]}; }
  Vec3 faceNormal() const { return {normal[0], normal[1], normal[2]}; }
};

// A smooth one: its unit vertex normals (n1 and n2 swapped with their corners) and `perp`,
// whose dot product with (point - p1) is the point's weight u of the edge p2-p3
// (compute_smooth_triangle), and the axis along which v is measured.
struct PovMeshSmoothTriangleShape : PovMeshTriangleShape {
  float n[3][3] = {};
  float perp[3] = {};
  uint8_t vAxis = 0;

  Vec3 vertexNormal(int i) const { return {n[i][0], n[i][1], n[i][2]}; }
};

// Parse_Mesh's making of a mesh's triangles, one at a time in the order POV-Ray reads them
// (the exporter writes a mesh's triangles first, then its smooth triangles). POV-Ray keeps
// each distinct vertex and normal once, looked up in hash tables that take any stored
// float within 1e-10 in every coordinate for the new one (mesh_hash); the lookup is done
// here the same way, so that a value a hair from 0 becomes the 0 stored before it, as in
// POV-Ray.
class PovMeshBuilder {
 public:
  PovMeshBuilder();
  // `triangle { p1, p2, p3 }`: kNever when its corners are on a line (Mesh::Degenerate).
  PovMeshTriangleShape triangle(const Vec3& p1, const Vec3& p2, const Vec3& p3);
  // `smooth_triangle { p1, n1, p2, n2, p3, n3 }`: a flat triangle when its unit vertex
  // normals are all within 1e-10 (squared distance) of n1, as POV-Ray's parser makes it.
  // Its `axis` is kNever where POV-Ray leaves it out.
  PovMeshSmoothTriangleShape smoothTriangle(const Vec3& p1, Vec3 n1, const Vec3& p2, Vec3 n2, const Vec3& p3,
                                            Vec3 n3, bool& smooth);

 private:
  // mesh_hash: the float stored for `v`, a new one or one within 1e-10 of it.
  class Table {
   public:
    Table();
    std::array<float, 3> find(const Vec3& v);

   private:
    std::vector<std::array<float, 3>> values_;
    std::vector<std::vector<uint32_t>> buckets_;
  };
  // Compute_Mesh_Triangle (and compute_smooth_triangle) from the corners as written.
  bool setUp(PovMeshTriangleShape& t, Vec3 p1, Vec3 p2, Vec3 p3, bool& swapped, std::array<float, 3>* perp,
             uint8_t* vAxis);

  Table vertices_, normals_;
};

// intersect_mesh_triangle: the depth along a mesh-space ray of unit direction, at least
// `minDepth` (POV-Ray's DEPTH_TOLERANCE, times the scene's unit), or nothing.
std::optional<double> hitPovMeshTriangle(const PovMeshTriangleShape& t, const Vec3& origin, const Vec3& dir,
                                         double minDepth);
// Smooth_Mesh_Normal at the mesh-space point `at`: not yet made unit.
Vec3 povSmoothMeshNormal(const PovMeshSmoothTriangleShape& t, const Vec3& at);

}  // namespace pvrt
