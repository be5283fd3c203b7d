#include "dsp/fft_wisdom.h"

#include <fftw3.h>

namespace bouncecal::audio {
namespace {

#include "dsp/fftwf_wisdom.inc"

}  // namespace

bool ImportShippedFftwfWisdom() {
  // Once: importing again would only repeat the same entries.
  static const bool accepted = fftwf_import_wisdom_from_string(kFftwfWisdom) != 0;
  return accepted;
}

}  // namespace bouncecal::audio
