#include "viewer/viewer_failure.h"

namespace rt {

const char* failure_name(ViewerFailure failure) {
  switch (failure) {
    case ViewerFailure::None: return "none";
    case ViewerFailure::InvalidInput: return "invalid input";
    case ViewerFailure::EyesNotFound: return "eyes not found";
    case ViewerFailure::TooFewViews: return "too few views";
    case ViewerFailure::RaysNearlyParallel: return "rays nearly parallel";
    case ViewerFailure::BehindCamera: return "behind a camera";
    case ViewerFailure::NotInFrontOfScreen: return "not in front of the screen";
    case ViewerFailure::ReprojectionTooLarge: return "reprojection error too large";
    case ViewerFailure::EyesImplausible: return "eyes implausible";
    case ViewerFailure::TooFewFrames: return "too few frames";
    case ViewerFailure::Unsteady: return "unsteady";
  }
  return "unknown";
}

}  // namespace rt
