#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "render/colour_scale.h"
#include "render/png_file.h"
#include "render/rasterizer.h"
#include "render/text.h"
#include "render/views.h"
#include "testing/test_meshes.h"

namespace fs = std::filesystem;
using gp::render::Image;

namespace {

// Height colour of the test scene: linear in y, so that its interpolation
// over a flat triangle is exact at every point the orthographic ray hits.
Eigen::Vector3f height_colour(double y) {
  const float t = static_cast<float>(0.5 + 0.5 * y);
  return {0.15f + 0.8f * t, 0.35f, 0.95f - 0.8f * t};
}

struct SphereScene {
  gp::Mesh sphere = gp::testing::make_icosphere(5);  // 10,242 vertices
  Eigen::MatrixXf colours;
  gp::render::OrthoCamera camera;
  SphereScene() {
    colours.resize(sphere.V.rows(), 3);
    for (Eigen::Index v = 0; v < sphere.V.rows(); ++v) colours.row(v) = height_colour(sphere.V(v, 1)).transpose();
    camera.width = camera.height = 200;
    camera.pixels_per_metre = 80.0;  // the unit sphere is 160 pixels across
  }
  Image render(int supersampling) const {
    gp::render::MeshLayer layer;
    layer.V = &sphere.V;
    layer.F = &sphere.F;
    layer.vertex_colours = &colours;
    gp::render::RenderOptions options;
    options.supersampling = supersampling;
    return gp::render::render({layer}, camera, options);
  }
};

}  // namespace

// The reference is analytic rather than a stored picture: at pixel (x, y) the
// unit sphere seen from +z has the normal (x, y, sqrt(1 - x^2 - y^2)), so the
// expected colour is albedo(y) * (ambient + diffuse * max(0, n . light)). The
// mesh differs from the sphere by its faceting (normals interpolated across
// 20,480 triangles, depth error under 0.1 %) and by supersampling, which
// averages the colour over the pixel: measured at most 1 level in 255 and
// 0.02 on average inside the disk. Pixels on the silhouette (within 2 pixels
// of the radius) are mixed with the background and not compared.
TEST_CASE("a unit sphere coloured by height renders as the analytic sphere", "[render]") {
  const SphereScene scene;
  const gp::render::Shading shading;
  const Eigen::Vector3f light = shading.light.normalized();
  for (int supersampling : {1, 3}) {
    const Image image = scene.render(supersampling);
    REQUIRE(image.width == 200);
    REQUIRE(image.height == 200);
    int compared = 0, background = 0, worst = 0;
    double total_error = 0.0;
    for (int py = 0; py < image.height; ++py)
      for (int px = 0; px < image.width; ++px) {
        const double x = (px + 0.5 - 100.0) / 80.0, y = (100.0 - (py + 0.5)) / 80.0;
        const double r = std::sqrt(x * x + y * y);
        const std::uint8_t* p = image.at(px, py);
        if (r > 1.0 + 2.0 / 80.0) {
          CHECK((p[0] == 255 && p[1] == 255 && p[2] == 255));
          ++background;
          continue;
        }
        if (r > 1.0 - 2.0 / 80.0) continue;
        const Eigen::Vector3f n(static_cast<float>(x), static_cast<float>(y), static_cast<float>(std::sqrt(1.0 - r * r)));
        const float shade = shading.ambient + shading.diffuse * std::max(0.0f, n.dot(light));
        const Eigen::Vector3f expected = height_colour(y) * shade;
        for (int c = 0; c < 3; ++c) {
          const int e = std::abs(static_cast<int>(p[c]) - static_cast<int>(gp::render::to_byte(expected(c))));
          worst = std::max(worst, e);
          total_error += e;
        }
        ++compared;
      }
    INFO("supersampling " << supersampling << ": worst " << worst << ", mean " << total_error / (3.0 * compared));
    CHECK(compared > 18000);
    CHECK(background > 15000);
    CHECK(worst <= 2);
    CHECK(total_error / (3.0 * compared) < 0.1);
  }
}

TEST_CASE("renders are deterministic and PNG files round-trip", "[render]") {
  const SphereScene scene;
  const Image a = scene.render(3);
  const Image b = scene.render(3);
  CHECK(a.pixels == b.pixels);
  CHECK(gp::render::encode_png(a) == gp::render::encode_png(b));
  const fs::path path = fs::temp_directory_path() / "gp_render_test_sphere.png";
  gp::render::write_png(path, a);
  const Image c = gp::render::read_png(path);
  CHECK(c.width == a.width);
  CHECK(c.pixels == a.pixels);
  fs::remove(path);
  CHECK_THROWS_AS(gp::render::read_png(fs::temp_directory_path() / "gp_render_test_missing.png"), gp::InputError);
}

TEST_CASE("the nearer surface hides the farther one, on either side of a triangle", "[render]") {
  // Two quads facing the camera, a red one behind a blue one that covers its
  // left half; the blue one is wound clockwise (its back faces the viewer).
  Eigen::MatrixXd V(8, 3);
  V << -1, -1, -0.5, 1, -1, -0.5, 1, 1, -0.5, -1, 1, -0.5,  // far, red
      -1, -1, 0.5, 0, -1, 0.5, 0, 1, 0.5, -1, 1, 0.5;       // near, blue
  Eigen::MatrixXi F_far(2, 3), F_near(2, 3);
  F_far << 0, 1, 2, 0, 2, 3;
  F_near << 4, 6, 5, 4, 7, 6;
  gp::render::MeshLayer far{&V, &F_far, nullptr, nullptr, {1.0f, 0.0f, 0.0f}};
  gp::render::MeshLayer near{&V, &F_near, nullptr, nullptr, {0.0f, 0.0f, 1.0f}};
  gp::render::OrthoCamera camera;
  camera.width = camera.height = 40;
  camera.pixels_per_metre = 15.0;
  gp::render::RenderOptions options;
  options.supersampling = 1;
  for (const auto& order : {std::vector<gp::render::MeshLayer>{far, near}, std::vector<gp::render::MeshLayer>{near, far}}) {
    const Image image = gp::render::render(order, camera, options);
    const std::uint8_t* left = image.at(12, 20);
    const std::uint8_t* right = image.at(28, 20);
    CHECK((left[2] > 0 && left[0] == 0));
    CHECK((right[0] > 0 && right[2] == 0));
    // The blue quad shows its back: darker than a front-facing one would be.
    const gp::render::Shading s;
    const float front = s.ambient + s.diffuse * s.light.normalized().z();
    CHECK(left[2] == gp::render::to_byte(front * s.back_factor));
  }
}

TEST_CASE("degenerate and non-finite triangles are skipped, bad input rejected", "[render]") {
  Eigen::MatrixXd V(6, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0,  // collinear
      0, 0, 0, 1, std::nan(""), 0, 0, 1, 0;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 3, 4, 5;
  gp::render::MeshLayer layer{&V, &F, nullptr, nullptr, {0.0f, 0.0f, 0.0f}};
  gp::render::OrthoCamera camera;
  camera.width = camera.height = 16;
  const Image image = gp::render::render({layer}, camera);
  for (std::uint8_t p : image.pixels) CHECK(p == 255);
  Eigen::MatrixXi bad = F;
  bad(0, 0) = 6;
  CHECK_THROWS_AS(gp::render::render({{&V, &bad, nullptr, nullptr, {}}}, camera), gp::UsageError);
  gp::render::RenderOptions options;
  options.supersampling = 0;
  CHECK_THROWS_AS(gp::render::render({layer}, camera, options), gp::UsageError);
  camera.pixels_per_metre = 0.0;
  CHECK_THROWS_AS(gp::render::render({layer}, camera), gp::UsageError);
}

TEST_CASE("the stretch scale is fixed, cool below the limit and warm above it", "[render]") {
  const gp::render::ColourScale s = gp::render::stretch_scale(0.1);
  CHECK(s.min_value() == 1.0);
  CHECK(s.max_value() == Approx(1.3));
  const gp::render::Rgb below = s.colour(1.05), above = s.colour(1.2), under = s.colour(0.9), over = s.colour(2.0);
  CHECK(below.b > below.r);
  CHECK(above.r > above.b);
  CHECK(under.b == s.colour(1.0).b);   // compression takes the low end
  CHECK(over.r == s.colour(1.3).r);    // the high end is clamped
  CHECK(s.position(1.15) == Approx(0.5));
  bool limit_marked = false;
  for (const auto& t : s.ticks()) limit_marked |= t.marked && std::abs(t.value - 1.1) < 1e-12;
  CHECK(limit_marked);
  CHECK_THROWS_AS(gp::render::stretch_scale(0.0), gp::UsageError);
  const gp::render::ColourScale g = gp::render::growth_scale();
  CHECK(g.position(1.0) == Approx(0.5));  // log axis: 0.5 .. 2 around 1
  CHECK(g.value_at(0.75) == Approx(std::sqrt(2.0)));
}

TEST_CASE("front, side and back views look at the body from its front, left and back", "[render]") {
  const Eigen::Vector3d front = Eigen::Vector3d::UnitZ();
  const auto f = gp::render::view_axes(gp::render::View::front, front);
  const auto s = gp::render::view_axes(gp::render::View::side, front);
  const auto b = gp::render::view_axes(gp::render::View::back, front);
  CHECK(f.right.cross(f.up).isApprox(front));        // towards the viewer
  CHECK(b.right.cross(b.up).isApprox(-front));
  CHECK(s.right.cross(s.up).isApprox(Eigen::Vector3d::UnitX()));  // the body's left, facing +z
  CHECK_THROWS_AS(gp::render::view_axes(gp::render::View::front, Eigen::Vector3d::UnitY()), gp::UsageError);
}

TEST_CASE("text is drawn with the installed font", "[render]") {
  const gp::render::Font font(gp::render::default_font_path());
  Image image(120, 30, {1.0f, 1.0f, 1.0f});
  font.draw(image, 2, 20, "1+\xce\xb4 = 1.10", 14, {0.0f, 0.0f, 0.0f});
  int dark = 0;
  for (std::uint8_t p : image.pixels) dark += p < 128;
  CHECK(dark > 60);
  CHECK(font.width("1.10", 14) > font.width("1", 14));
  CHECK_THROWS_AS(gp::render::Font("/nonexistent/font.ttf"), gp::InputError);
}

// A mark drawn over a render must sit on the point it marks: project() is
// checked against the rasterizer on the sphere's silhouette, whose extreme
// points land at the image centre +-80 pixels in a turned camera too.
TEST_CASE("project() maps a world point where the rasterizer draws it, and a ring marks around it", "[render]") {
  SphereScene scene;
  scene.camera.right = Eigen::Vector3d(1.0, 0.0, 1.0).normalized();  // a camera turned 45 degrees about y
  scene.camera.center = Eigen::Vector3d(0.25, 0.0, 0.0);
  const Image image = scene.render(1);
  const Eigen::Vector3d rightmost = Eigen::Vector3d(0.0, 0.0, 0.0) + scene.camera.right.normalized();
  const Eigen::Vector2d p = gp::render::project(scene.camera, rightmost);
  CHECK(p.x() == Approx(100.0 + 80.0 * (1.0 - 0.25 * std::sqrt(0.5))).margin(1e-9));
  CHECK(p.y() == Approx(100.0).margin(1e-9));
  // The sphere is drawn just inside that point and not just outside it.
  auto background = [&](int x, int y) {
    const std::uint8_t* c = image.at(x, y);
    return c[0] == 255 && c[1] == 255 && c[2] == 255;
  };
  CHECK_FALSE(background(static_cast<int>(p.x()) - 2, 100));
  CHECK(background(static_cast<int>(p.x()) + 2, 100));

  Image canvas(64, 64, gp::render::Rgb{1.0f, 1.0f, 1.0f});
  gp::render::draw_ring(canvas, 32.0, 32.0, 10.0, 3.0, gp::render::Rgb{1.0f, 0.0f, 1.0f});
  auto magenta = [&](int x, int y) {
    const std::uint8_t* c = canvas.at(x, y);
    return c[0] == 255 && c[1] == 0 && c[2] == 255;
  };
  CHECK(magenta(42, 32));   // pixel centre 10.5 from the centre: on the ring
  CHECK(magenta(32, 21));   // 10.5 above
  CHECK_FALSE(magenta(32, 32));  // the centre stays clear, so the place shows
  CHECK_FALSE(magenta(46, 32));  // 14.5: outside
  int coloured = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) coloured += magenta(x, y);
  // The annulus of radii 8.5 and 11.5 has area pi (11.5^2 - 8.5^2) = 188.5 pixels.
  CHECK(coloured == Approx(188.5).margin(12.0));
  gp::render::draw_ring(canvas, -100.0, -100.0, 5.0, 2.0, gp::render::Rgb{});  // wholly outside: clipped, no throw
}
