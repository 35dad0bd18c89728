#include "uavip/photo/renderer.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace uavip::photo {
namespace {

/// The fixed light of the shading (unit; only |n·l| counts).
const Vec3 kLight = Vec3(0.35, 0.55, 0.76).normalized();

/// Rounds [0, 1] to a byte.
std::uint8_t toByte(double v) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
}

/// libpng's write callback: appends to the std::string in the io pointer.
void appendBytes(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::string*>(png_get_io_ptr(png));
  out->append(reinterpret_cast<const char*>(data), length);
}

void noFlush(png_structp /*png*/) {}

/// Writes the PNG into `out`; false when libpng reports an error (its longjmp lands
/// here, where no C++ object needs unwinding).
bool writePng(const Image& image, png_bytep* rows, std::string* out) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {  // NOLINT(cert-err52-cpp): libpng's error path
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, out, appendBytes, noFlush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width),
               static_cast<png_uint_32>(image.height), 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_rows(png, info, rows);
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

PhotoPose poseFromView(const coverage::ViewPose& view) {
  const coverage::ViewFrame f = coverage::makeViewFrame(view);
  PhotoPose pose;
  pose.position = view.position;
  pose.camera_to_world.col(0) = f.right;
  pose.camera_to_world.col(1) = -f.up;
  pose.camera_to_world.col(2) = f.forward;
  return pose;
}

Vec3 pixelRay(const coverage::PinholeIntrinsics& k, const PhotoPose& pose, double x, double y) {
  const Vec3 c((x - k.cx_px) / k.fx_px, (y - k.cy_px) / k.fy_px, 1.0);
  return (pose.camera_to_world * c).normalized();
}

Eigen::Vector3d projectToImage(const coverage::PinholeIntrinsics& k, const PhotoPose& pose,
                               const Vec3& p) {
  const Vec3 c = pose.camera_to_world.transpose() * (p - pose.position);
  return {k.fx_px * c.x() / c.z() + k.cx_px, k.fy_px * c.y() / c.z() + k.cy_px, c.z()};
}

Image renderPhoto(const RayCaster& world, const SurfaceTexture& texture,
                  const coverage::PinholeIntrinsics& k, const PhotoPose& pose) {
  Image image;
  image.width = k.width_px;
  image.height = k.height_px;
  image.rgb.resize(static_cast<std::size_t>(k.width_px) * static_cast<std::size_t>(k.height_px) *
                   3);
  const double pixel_per_m = std::sqrt(k.fx_px * k.fy_px);
  std::size_t at = 0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u, at += 3) {
      const Vec3 dir = pixelRay(k, pose, u + 0.5, v + 0.5);
      const RayHit hit = world.cast(pose.position, dir);
      if (!hit.hit) {
        std::copy(kSkyRgb, kSkyRgb + 3, image.rgb.begin() + static_cast<std::ptrdiff_t>(at));
        continue;
      }
      const auto albedo = texture.albedo(hit.point, hit.t / pixel_per_m);
      const double shade = 0.55 + 0.45 * std::abs(hit.normal.dot(kLight));
      for (std::size_t c = 0; c < 3; ++c) image.rgb[at + c] = toByte(albedo[c] * shade);
    }
  }
  return image;
}

std::string encodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() !=
          static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument("encodePng: the image's size does not match its pixels");
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  auto* data = const_cast<std::uint8_t*>(image.rgb.data());  // libpng only reads the rows
  for (std::size_t r = 0; r < rows.size(); ++r)
    rows[r] = data + r * static_cast<std::size_t>(image.width) * 3;
  std::string out;
  out.reserve(image.rgb.size() / 2);
  if (!writePng(image, rows.data(), &out)) throw std::runtime_error("libpng: writing a PNG failed");
  return out;
}

}  // namespace uavip::photo
