#include "map/map_points_text.h"

#include <iomanip>

#include "core/atomic_file.h"

namespace dynslam {

cv::Vec3b mapPointBgr(const MapPoint& mp) {
  if (mp.ref_kf) {
    auto it = mp.obs.find(mp.ref_kf);
    if (it != mp.obs.end()) return mp.ref_kf->f().colors[it->second];
  }
  return cv::Vec3b(200, 200, 200);
}

void writeMapPointsText(const std::string& path, const Map& map) {
  writeFileAtomically(path, [&](std::ostream& os) {
    os << "# x y z r g b (world frame, colour of the reference keyframe's pixel)\n";
    os << std::setprecision(7);
    for (MapPoint* mp : map.mapPoints()) {
      const cv::Vec3b bgr = mapPointBgr(*mp);
      os << mp->pos.x() << ' ' << mp->pos.y() << ' ' << mp->pos.z() << ' ' << int(bgr[2]) << ' '
         << int(bgr[1]) << ' ' << int(bgr[0]) << '\n';
    }
  });
}

}  // namespace dynslam
