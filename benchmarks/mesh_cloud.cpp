// A triangle mesh of a point cloud for the photo check of real structures (issue 46
// item 5): PCL's greedy projection triangulation (GP3, Marton et al. 2009) over the
// cloud's own points, so the mesh passes through every measured point and invents no
// surface where none was scanned (Poisson closes holes with surface the scan never saw).
//
//   uavip_mesh_cloud CLOUD -o MESH.ply [--radius-factor F] [--k K]
//
// Normals: PCL's NormalEstimation over the K nearest points (default 20). The search
// radius is F (default 6) times the cloud's median nearest-neighbour spacing. The mesh
// is written as a binary PLY with faces (read back by uavip as a mesh) in the cloud's
// file coordinates, as read (input.scale 1, not recentred: the FC-Planner clouds are small).

#include <pcl/PolygonMesh.h>
#include <pcl/features/normal_3d.h>
#include <pcl/io/ply_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/gp3.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "uavip/core/error.h"
#include "uavip/core/pcl_cloud.h"
#include "uavip/io/cloud_io.h"

namespace {

/// Median distance from a point to its nearest neighbour [m].
double medianSpacing(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud) {
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  std::vector<float> d;
  std::vector<int> idx(2);
  std::vector<float> sq(2);
  for (const auto& p : cloud->points) {
    if (tree.nearestKSearch(p, 2, idx, sq) == 2) d.push_back(std::sqrt(sq[1]));
  }
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string cloud_path, out;
  double radius_factor = 6.0;
  int k = 20;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-o" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--radius-factor" && i + 1 < argc) {
      radius_factor = std::stod(argv[++i]);
    } else if (a == "--k" && i + 1 < argc) {
      k = std::stoi(argv[++i]);
    } else if (cloud_path.empty() && a[0] != '-') {
      cloud_path = a;
    } else {
      std::cerr << "usage: uavip_mesh_cloud CLOUD -o MESH.ply [--radius-factor F] [--k K]\n";
      return 2;
    }
  }
  if (cloud_path.empty() || out.empty()) {
    std::cerr << "usage: uavip_mesh_cloud CLOUD -o MESH.ply [--radius-factor F] [--k K]\n";
    return 2;
  }
  try {
    const uavip::PointList points = uavip::io::loadCloud(cloud_path);
    const auto cloud = uavip::toPclCloud(points, uavip::Vec3::Zero());
    const double spacing = medianSpacing(cloud);
    auto tree = std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
    tree->setInputCloud(cloud);
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setInputCloud(cloud);
    ne.setSearchMethod(tree);
    ne.setKSearch(k);
    pcl::PointCloud<pcl::Normal> normals;
    ne.compute(normals);
    auto with_normals = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    pcl::concatenateFields(*cloud, normals, *with_normals);
    // GP3 wants finite normals: a point whose neighbourhood gave none gets +z.
    for (auto& p : with_normals->points) {
      if (!std::isfinite(p.normal_x) || !std::isfinite(p.normal_y) || !std::isfinite(p.normal_z)) {
        p.normal_x = p.normal_y = 0.0F;
        p.normal_z = 1.0F;
      }
    }
    auto tree2 = std::make_shared<pcl::search::KdTree<pcl::PointNormal>>();
    tree2->setInputCloud(with_normals);
    pcl::GreedyProjectionTriangulation<pcl::PointNormal> gp3;
    gp3.setSearchRadius(radius_factor * spacing);
    gp3.setMu(2.5);
    gp3.setMaximumNearestNeighbors(100);
    gp3.setMaximumSurfaceAngle(M_PI / 4);
    gp3.setMinimumAngle(M_PI / 18);
    gp3.setMaximumAngle(2 * M_PI / 3);
    gp3.setNormalConsistency(false);
    gp3.setInputCloud(with_normals);
    gp3.setSearchMethod(tree2);
    pcl::PolygonMesh mesh;
    gp3.reconstruct(mesh);
    if (mesh.polygons.empty()) throw uavip::InputError(cloud_path + ": GP3 made no triangle");
    const std::string tmp = out + ".tmp";
    if (pcl::io::savePLYFileBinary(tmp, mesh) != 0 || std::rename(tmp.c_str(), out.c_str()) != 0)
      throw uavip::InputError(out + ": cannot write the mesh");
    std::printf(
        "%s: %zu points, median spacing %.3f m, search radius %.3f m -> %zu triangles in %s\n",
        cloud_path.c_str(), points.size(), spacing, radius_factor * spacing, mesh.polygons.size(),
        out.c_str());
  } catch (const std::exception& e) {
    std::cerr << "uavip_mesh_cloud: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
