#ifndef BOUNCECAL_DEM_LAWS_LAW_COMMON_H_
#define BOUNCECAL_DEM_LAWS_LAW_COMMON_H_

namespace bouncecal::dem {

// One sphere-on-plane impact solved in closed form with gravity acting during the contact (the
// exact event-driven path of the single-ball drop). Only the piecewise-linear laws provide it.
struct ExactImpact {
  // False when the ball never leaves the plane again (it comes to rest in contact, or the law
  // returns no energy at all): the remaining fields then describe the contact up to maximum
  // compression and speed_out_mps is 0.
  bool released = false;
  double duration_s = 0;     // onset (overlap 0, approaching) to release (overlap 0, leaving)
  double max_overlap_m = 0;  // deepest compression
  double speed_out_mps = 0;  // speed at release, overlap 0
};

}  // namespace bouncecal::dem

#endif  // BOUNCECAL_DEM_LAWS_LAW_COMMON_H_
