#pragma once
// The simulated user's face: a real frontal photograph (Debian's opencv-doc, the one the viewer's
// tests use) printed on the front of the head by a planar projection along the head's forward
// axis, scaled and placed so that its marked pupils sit at the user's eyes. The cameras then see
// a face that the Haar cascades find, as at a real site, and the simulator knows where the eyes
// truly are (true_eyes), to measure the viewpoint the site computes from its cameras.
//
// Head frame: origin the head centre, +x the user's right, +y up, +z backwards (the site frame of
// a user sitting upright, facing the screen); PersonPose::head_rotation maps it into the site.
#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>

#include "image/host_image.h"
#include "sim/person_pose.h"

namespace rt::sim {

// A frontal portrait from OpenCV's face-landmark tutorial; $REMOTETOUCH_FACE_PHOTO overrides it.
inline constexpr const char* kDefaultFacePhoto = "/usr/share/doc/opencv-doc/opencv4/html/230501201_1.jpg";
std::filesystem::path face_photo_path();

// The simulated head: a capsule along the head's y, elliptic across (narrower than deep).
struct HeadShape {
  double half_length_m = 0.02;  // of the capsule's straight part, above and below the centre
  double width_radius_m = 0.085;
  double depth_radius_m = 0.1;
};
HeadShape head_shape(double head_radius_m);

// The face texture (rgba32f, as person_raster samples it): the photograph's face divided by its
// own skin color (so that it takes the user's skin color), alpha 1 on the face fading to 0 at
// its edge and on the texture's border. Empty, with `why`, when the photo cannot be read.
std::optional<HostImage> load_face_texture(std::string& why);

// Where a head-frame point lies on the face texture (u, v in [0, 1] on the texture), and how
// squarely it faces forward (1 on the face, 0 from the sides back), for the mesh's head vertices.
Eigen::Vector2d face_uv(const Eigen::Vector3d& head_point);
double face_facing(const Eigen::Vector3d& head_point, const HeadShape& shape);

// The pupils of the face on the head, in the site frame: the simulated user's true eyes.
struct TrueEyes {
  Eigen::Vector3d right = Eigen::Vector3d::Zero();  // the user's right eye
  Eigen::Vector3d left = Eigen::Vector3d::Zero();
  Eigen::Vector3d midpoint() const { return (right + left) / 2.0; }
};
TrueEyes true_eyes(const PersonPose& pose);
// Of a user sitting upright with the head at `head_centre_m` (the seat's head position).
TrueEyes true_eyes_seated(const Eigen::Vector3d& head_centre_m, double head_radius_m = 0.1);

}  // namespace rt::sim
