#include <doctest/doctest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/shading/surface.h"

using namespace cr;

namespace {

Primitive unit_triangle() {
  Primitive p;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  p.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  p.texcoords = {{0, 0}, {1, 0}, {0, 1}};
  p.colors = {{1, 0, 0, 1}, {0, 1, 0, 0.5f}, {0, 0, 1, 0}};
  p.tangents = {{1, 0, 0, -1}, {1, 0, 0, -1}, {1, 0, 0, -1}};
  p.indices = {0, 1, 2};
  return p;
}

Draw make_draw(const glm::mat4& world) {
  Draw d;
  d.world = world;
  d.normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
  d.mirrored = glm::determinant(glm::mat3(world)) < 0.0f;
  return d;
}

void check_vec(const glm::vec3& a, const glm::vec3& b) {
  for (int i = 0; i < 3; ++i) CHECK(a[i] == doctest::Approx(b[i]).epsilon(1e-5).scale(1.0));
}

void check_unit_frame(const SurfaceSample& s) {
  CHECK(glm::length(s.normal) == doctest::Approx(1.0f));
  CHECK(glm::length(glm::vec3(s.tangent)) == doctest::Approx(1.0f));
  CHECK(std::abs(glm::dot(s.normal, glm::vec3(s.tangent))) < 1e-5f);
  CHECK(std::abs(s.tangent.w) == 1.0f);
}

}  // namespace

TEST_CASE("surface: attributes interpolate with the given barycentrics into world space") {
  const Primitive p = unit_triangle();
  const Draw d = make_draw(glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)));
  Barycentrics b;
  b.b = {0.2f, 0.3f, 0.5f};
  b.ddx = {-0.01f, 0.01f, 0.0f};
  b.ddy = {-0.02f, 0.0f, 0.02f};
  const SurfaceSample s = interpolate_surface(p, d, 0, b, true);
  check_vec(s.position, {10.6f, 1.0f, 0.0f});
  check_vec(s.normal, {0, 0, 1});
  check_vec(glm::vec3(s.tangent), {1, 0, 0});
  CHECK(s.tangent.w == -1.0f);
  CHECK(s.uv.x == doctest::Approx(0.3f));
  CHECK(s.uv.y == doctest::Approx(0.5f));
  CHECK(s.duv_dx.x == doctest::Approx(0.01f));
  CHECK(s.duv_dx.y == doctest::Approx(0.0f));
  CHECK(s.duv_dy.x == doctest::Approx(0.0f));
  CHECK(s.duv_dy.y == doctest::Approx(0.02f));
  CHECK(s.color.r == doctest::Approx(0.2f));
  CHECK(s.color.g == doctest::Approx(0.3f));
  CHECK(s.color.b == doctest::Approx(0.5f));
  CHECK(s.color.a == doctest::Approx(0.35f));
  CHECK(s.front_facing);
}

TEST_CASE("surface: normals use the normal matrix under non-uniform scale") {
  Primitive p = unit_triangle();
  const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
  p.normals = {n, n, n};
  p.tangents = {{1, -1, 0, 1}, {1, -1, 0, 1}, {1, -1, 0, 1}};
  const Draw d = make_draw(glm::scale(glm::mat4(1.0f), glm::vec3(1, 2, 1)));
  Barycentrics b;
  b.b = {1.0f / 3, 1.0f / 3, 1.0f / 3};
  const SurfaceSample s = interpolate_surface(p, d, 0, b, true);
  // inverse-transpose of diag(1, 2, 1) is diag(1, 0.5, 1).
  check_vec(s.normal, glm::normalize(glm::vec3(1, 0.5f, 0)));
  check_unit_frame(s);
  // The tangent, carried by the world 3x3, stays tangent to the scaled surface.
  const glm::vec3 world_tangent = glm::normalize(glm::vec3(1, -2, 0));
  CHECK(glm::dot(glm::vec3(s.tangent), world_tangent) == doctest::Approx(1.0f));
}

TEST_CASE("surface: back faces flip the frame; mirrored draws flip the bitangent sign") {
  const Primitive p = unit_triangle();
  Barycentrics b;
  b.b = {0.2f, 0.3f, 0.5f};
  const SurfaceSample back = interpolate_surface(p, make_draw(glm::mat4(1.0f)), 0, b, false);
  check_vec(back.normal, {0, 0, -1});
  CHECK(!back.front_facing);
  const SurfaceSample front = interpolate_surface(p, make_draw(glm::mat4(1.0f)), 0, b, true);
  // The bitangent cross(N, T) * w is reversed too, so a normal map reads mirrored from behind.
  const glm::vec3 bf = glm::cross(front.normal, glm::vec3(front.tangent)) * front.tangent.w;
  const glm::vec3 bb = glm::cross(back.normal, glm::vec3(back.tangent)) * back.tangent.w;
  check_vec(bb, -bf);
  check_unit_frame(back);

  const Draw mirror = make_draw(glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)));
  CHECK(mirror.mirrored);
  const SurfaceSample m = interpolate_surface(p, mirror, 0, b, true);
  CHECK(m.tangent.w == 1.0f);  // the file's -1, flipped by the mirror
  // The mirrored bitangent is the mirror image of the original one (+Y stays +Y).
  check_vec(glm::cross(m.normal, glm::vec3(m.tangent)) * m.tangent.w, bf);
}

TEST_CASE("surface: missing streams take defaults; degenerate input stays finite") {
  Primitive p;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}};
  p.indices = {0, 1, 2};
  Barycentrics b;
  b.b = {0.2f, 0.3f, 0.5f};
  b.ddx = {1.0f, 2.0f, 3.0f};
  const SurfaceSample s = interpolate_surface(p, make_draw(glm::mat4(1.0f)), 0, b, true);
  CHECK(s.uv == glm::vec2(0.0f));
  CHECK(s.duv_dx == glm::vec2(0.0f));
  CHECK(s.color == glm::vec4(1.0f));
  check_vec(s.normal, {0, 1, 0});  // geometric normal of the counter-clockwise triangle
  check_unit_frame(s);

  // Zero normals and a collapsed triangle: still a unit, orthogonal frame.
  Primitive degenerate;
  degenerate.positions = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  degenerate.normals = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
  degenerate.tangents = {glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f)};
  degenerate.indices = {0, 1, 2};
  const SurfaceSample z = interpolate_surface(degenerate, make_draw(glm::mat4(1.0f)), 0, b, true);
  check_unit_frame(z);
  for (const glm::vec3& n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, -2, 3)),
                             glm::vec3(0, -1, 0)}) {
    const glm::vec3 t = orthogonal_tangent(n);
    CHECK(glm::length(t) == doctest::Approx(1.0f));
    CHECK(std::abs(glm::dot(t, n)) < 1e-6f);
  }
}

TEST_CASE("surface: skipping the tangent frame leaves every other attribute unchanged") {
  const Primitive p = unit_triangle();
  Primitive no_normals = p;
  no_normals.normals.clear();
  const Draw d = make_draw(glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(1, -2, 3)), 0.7f, glm::vec3(1, 1, 0)));
  Barycentrics b;
  b.b = {0.25f, 0.35f, 0.4f};
  b.ddx = {-0.02f, 0.01f, 0.01f};
  b.ddy = {0.0f, -0.03f, 0.03f};
  for (const Primitive* prim : {&p, static_cast<const Primitive*>(&no_normals)}) {
    for (bool front : {true, false}) {
      const SurfaceSample full = interpolate_surface(*prim, d, 0, b, front);
      const SurfaceSample lean = interpolate_surface(*prim, d, 0, b, front, false);
      for (int i = 0; i < 3; ++i) {
        CHECK(lean.position[i] == full.position[i]);
        CHECK(lean.normal[i] == full.normal[i]);
      }
      CHECK(lean.uv == full.uv);
      CHECK(lean.duv_dx == full.duv_dx);
      CHECK(lean.duv_dy == full.duv_dy);
      CHECK(lean.color == full.color);
      CHECK(lean.front_facing == full.front_facing);
      CHECK(lean.tangent == SurfaceSample{}.tangent);
    }
  }
}

TEST_CASE("surface: the coverage-only interpolation gives the full sample's uv, derivatives and colour") {
  Primitive p = unit_triangle();
  p.colors = {glm::vec4(1.0f, 0.5f, 0.25f, 0.1f), glm::vec4(0.2f, 0.4f, 0.6f, 0.9f), glm::vec4(0.0f, 1.0f, 0.0f, 0.5f)};
  Primitive bare = p;
  bare.texcoords.clear();
  bare.colors.clear();
  const Draw d = make_draw(glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(0, 1, 0)));
  Barycentrics b;
  b.b = {0.6f, 0.15f, 0.25f};
  b.ddx = {0.01f, -0.02f, 0.01f};
  b.ddy = {-0.03f, 0.0f, 0.03f};
  for (const Primitive* prim : {static_cast<const Primitive*>(&p), static_cast<const Primitive*>(&bare)}) {
    const SurfaceSample full = interpolate_surface(*prim, d, 0, b, true, false);
    const SurfaceSample lean = interpolate_uv_color(*prim, 0, b);
    CHECK(lean.uv == full.uv);
    CHECK(lean.duv_dx == full.duv_dx);
    CHECK(lean.duv_dy == full.duv_dy);
    CHECK(lean.color == full.color);
  }
  CHECK(interpolate_uv_color(p, 0, b).color != SurfaceSample{}.color);  // the colours were read
}
