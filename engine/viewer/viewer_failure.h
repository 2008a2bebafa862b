#pragma once
// Why a viewpoint could not be computed. Per-frame failures are expected (the viewer looks away,
// a camera is occluded), so they are results, not exceptions; set-up errors throw.
namespace rt {

enum class ViewerFailure {
  None,
  InvalidInput,           // a NaN, an empty image, a pixel outside the image, an unknown camera
  EyesNotFound,           // the detector found no face or no pair of eyes in a view
  TooFewViews,            // fewer than two views see the eye
  RaysNearlyParallel,     // the views' rays meet at too small an angle for a depth
  BehindCamera,           // the rays meet behind one of the cameras
  NotInFrontOfScreen,     // the point is on or behind the screen plane (site z <= limit)
  ReprojectionTooLarge,   // the views disagree: the point does not reproject onto the detections
  EyesImplausible,        // the two eyes are not a human eye distance apart
  TooFewFrames,           // the start-up estimate has not seen the eyes in enough frames yet
  Unsteady,               // the start-up frames disagree more than the viewer's head should move
};

const char* failure_name(ViewerFailure failure);

}  // namespace rt
