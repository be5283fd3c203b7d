#include "dsp/fft_wisdom.h"

#include <fftw3.h>

#include <string>

namespace bouncecal::audio {
namespace {

#include "dsp/fftwf_wisdom.inc"

}  // namespace

std::string_view ShippedFftwfWisdom() { return kFftwfWisdom; }

bool ImportShippedFftwfWisdom() {
  // Once: importing again would only repeat the same entries.
  static const bool accepted = [] {
    const std::string text(ShippedFftwfWisdom());
    return fftwf_import_wisdom_from_string(text.c_str()) != 0;
  }();
  return accepted;
}

}  // namespace bouncecal::audio
