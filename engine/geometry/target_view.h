#pragma once
// The target view (DESIGN.md section 2): site S renders its user for viewer R. R's eye, mapped
// into S's frame, sits behind S's screen (z < 0); the generalized perspective projection whose
// window is S's screen rectangle (Kooima) lands the image one-to-one on R's screen pixels.
// Because the window is parallel to the image plane, that projection is a pinhole camera with
// a shifted principal point, facing +z, its image x running along R's +x (S's -x).
#include <Eigen/Core>

#include "geometry/camera.h"
#include "geometry/site_frames.h"

namespace rt {

// eye_in_site: the remote viewer's eye in this site's frame. Throws when the eye is on or
// behind the screen plane as the remote viewer sees it (z >= 0 here), or not finite.
Camera target_view_camera(const Eigen::Vector3d& eye_in_site, const Screen& screen, uint32_t width, uint32_t height);

}  // namespace rt
