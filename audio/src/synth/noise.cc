#include "synth/noise.h"

#include <cmath>

namespace bouncecal::audio {
namespace {

class NoiseGenerator {
 public:
  NoiseGenerator(NoiseColor color, const RandomStream& random) : color_(color), random_(random) {}

  double Next() {
    const double white = random_.Gaussian();
    if (color_ == NoiseColor::kWhite) return white;
    b0_ = 0.99886 * b0_ + white * 0.0555179;
    b1_ = 0.99332 * b1_ + white * 0.0750759;
    b2_ = 0.96900 * b2_ + white * 0.1538520;
    b3_ = 0.86650 * b3_ + white * 0.3104856;
    b4_ = 0.55000 * b4_ + white * 0.5329522;
    b5_ = -0.7616 * b5_ - white * 0.0168980;
    const double pink = b0_ + b1_ + b2_ + b3_ + b4_ + b5_ + b6_ + white * 0.5362;
    b6_ = white * 0.115926;
    return pink;
  }

 private:
  NoiseColor color_;
  RandomStream random_;
  double b0_ = 0, b1_ = 0, b2_ = 0, b3_ = 0, b4_ = 0, b5_ = 0, b6_ = 0;
};

}  // namespace

void AddNoise(NoiseColor color, double target_rms, const RandomStream& random,
              std::span<float> signal) {
  if (signal.empty() || target_rms <= 0.0) return;
  // Pass 1: the realisation's mean and power (Welford-free sums are exact enough in double for
  // the 1e9 samples of a long file: relative error ~1e-7 on the power).
  NoiseGenerator measure(color, random);
  double sum = 0.0;
  double sum_squares = 0.0;
  for (size_t i = 0; i < signal.size(); ++i) {
    const double value = measure.Next();
    sum += value;
    sum_squares += value * value;
  }
  const double count = static_cast<double>(signal.size());
  const double mean = sum / count;
  // The realised mean is removed so the noise adds no DC of its own (DC is its own impairment).
  const double power = sum_squares / count - mean * mean;
  if (power <= 0.0) return;
  const double scale = target_rms / std::sqrt(power);
  NoiseGenerator add(color, random);
  for (float& sample : signal) {
    sample += static_cast<float>((add.Next() - mean) * scale);
  }
}

}  // namespace bouncecal::audio
