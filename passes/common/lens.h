#pragma once
// A camera's intrinsics in the shaders' form (shared/config.h's IbrLens, common/lens.glsl); its
// C++ maths for the references is in ibr_scene.h (lens_pixel), beside the camera table's.
#include "geometry/camera.h"
#include "shared/config.h"

namespace rt::passes {

shader_abi::IbrLens lens_of(const CameraIntrinsics& intrinsics);

}  // namespace rt::passes
