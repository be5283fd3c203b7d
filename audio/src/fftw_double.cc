#include "fftw_double.h"

#include <new>

namespace bouncecal::audio::fftw_double {

std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

void PlanDestroy::operator()(fftw_plan_s* plan) const {
  std::lock_guard lock(PlannerMutex());
  fftw_destroy_plan(plan);
}

Plan PlanRealToComplex(int size, double* in, fftw_complex* out) {
  std::lock_guard lock(PlannerMutex());
  Plan plan(fftw_plan_dft_r2c_1d(size, in, out, FFTW_ESTIMATE));
  if (!plan) throw std::bad_alloc();
  return plan;
}

Plan PlanComplexToReal(int size, fftw_complex* in, double* out) {
  std::lock_guard lock(PlannerMutex());
  Plan plan(fftw_plan_dft_c2r_1d(size, in, out, FFTW_ESTIMATE));
  if (!plan) throw std::bad_alloc();
  return plan;
}

}  // namespace bouncecal::audio::fftw_double
