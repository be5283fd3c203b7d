#ifndef BOUNCECAL_AUDIO_SRC_FFTW_DOUBLE_H_
#define BOUNCECAL_AUDIO_SRC_FFTW_DOUBLE_H_

#include <fftw3.h>

#include <memory>
#include <mutex>

namespace bouncecal::audio::fftw_double {

// RAII owners of double-precision FFTW (libfftw3) buffers and plans. FFTW's planner is not
// thread-safe (FFTW manual, "Thread safety"): every plan of this precision is made and destroyed
// under PlannerMutex(); executing a plan needs no lock. Single precision is a separate library
// with its own planner, wrapped by RealFft.
std::mutex& PlannerMutex();

struct Free {
  void operator()(void* pointer) const { fftw_free(pointer); }
};
struct PlanDestroy {
  void operator()(fftw_plan_s* plan) const;
};
using RealBuffer = std::unique_ptr<double[], Free>;
using ComplexBuffer = std::unique_ptr<fftw_complex[], Free>;
using Plan = std::unique_ptr<fftw_plan_s, PlanDestroy>;

// FFTW_ESTIMATE plans (deterministic: measured plans would depend on timing); throw
// std::bad_alloc when FFTW cannot make them.
Plan PlanRealToComplex(int size, double* in, fftw_complex* out);
Plan PlanComplexToReal(int size, fftw_complex* in, double* out);

}  // namespace bouncecal::audio::fftw_double

#endif  // BOUNCECAL_AUDIO_SRC_FFTW_DOUBLE_H_
