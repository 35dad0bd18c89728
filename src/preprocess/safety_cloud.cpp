#include "uavip/preprocess/safety_cloud.h"

#include <cmath>
#include <limits>

#include "uavip/core/error.h"
#include "uavip/core/geometry.h"
#include "uavip/core/key_sort.h"
#include "uavip/core/text.h"
#include "uavip/core/voxel_key.h"

namespace uavip::preprocess {

void SafetyOptions::validate(const std::string& where) const { table().check(*this, where); }

const params::Table<SafetyOptions>& SafetyOptions::table() {
  static const params::Table<SafetyOptions> t = [] {
    using O = SafetyOptions;
    params::Table<O> p;
    p.add("cell_m", &O::cell_m,
          "thinning lattice of every measured point; its diagonal is added to every clearance")
        .unitIs("m")
        .above(0)
        .atMost(1);
    p.add("sparse_factor", &O::sparse_factor,
          "× the cloud's spacing kept from the points (0.71: a planar surface between its "
          "points; 0 trusts the points)")
        .within(0, 5);
    return p;
  }();
  return t;
}

SafetyCloud safetyCloud(const PointList& raw, double cell_m) {
  requirePositive(cell_m, "safety", "cell_m");
  SafetyCloud out;
  out.input_points = raw.size();
  if (raw.empty()) {
    out.cell_m = cell_m;
    out.margin_m = std::sqrt(3.0) * cell_m;
    return out;
  }
  for (std::size_t i = 0; i < raw.size(); ++i) {
    if (!raw[i].allFinite())
      throw InputError("cloud: point " + std::to_string(i) + " is not finite");
  }
  const Aabb box = boundingBox(raw);
  // A cell edge the 21-bit key can hold over this extent (2 cells of slack for the
  // lattice's floored origin).
  const double span = (box.max - box.min).maxCoeff();
  const double cell = std::max(cell_m, span / static_cast<double>(VoxelKeyer::kCells - 2));
  const SafetyOptions defaults;
  const VoxelKeyer keyer(box.min, box.max, cell,
                         "safety." + SafetyOptions::table().find(defaults, &defaults.cell_m)->key);
  std::vector<KeyedIndex> keyed(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i)
    keyed[i] = {keyer.key(raw[i]), static_cast<std::uint32_t>(i)};
  sortByKey(keyed);  // stable: the first point of each cell comes first
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    if (i > 0 && keyed[i].first == keyed[i - 1].first) continue;
    const Vec3& p = raw[keyed[i].second];
    // Float-exact: the copy in cloud_safety.pcd reads back as the same doubles.
    out.points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()),
                            static_cast<float>(p.z()));
  }
  out.cell_m = cell;
  // The cell's diagonal, plus what rounding to float may move a point (half an ulp
  // per axis at the cloud's largest coordinate).
  const double largest = std::max(box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff());
  const double rounding = std::sqrt(3.0) * largest * std::numeric_limits<float>::epsilon();
  out.margin_m = std::sqrt(3.0) * cell + rounding;
  return out;
}

double safetyMargin(const SafetyCloud& safety, double spacing_m, const SafetyOptions& options) {
  const double sparse =
      std::isfinite(spacing_m) && spacing_m > 0.0 ? options.sparse_factor * spacing_m : 0.0;
  return safety.margin_m + sparse;
}

}  // namespace uavip::preprocess
