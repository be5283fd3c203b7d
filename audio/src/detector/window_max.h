#ifndef BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_
#define BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_

#include <cstddef>
#include <span>
#include <vector>

namespace bouncecal::audio {

// The maximum of every run of `window` consecutive values of x (window >= 1, x.size() >= window):
// maxima[i] = max(x[i], ..., x[i + window - 1]) for i < x.size() - window + 1, as many as maxima
// holds. The detector's rise windows are sliding maxima over a whole filter block of frames at a
// time, so they need no state carried frame by frame: passes of pairwise maxima double the span
// each value covers (1, 2, 4, ... w <= window) and a last one joins two overlapping spans of w.
// Each pass is a loop without dependencies between its iterations (it vectorises), where a
// sliding maximum frame by frame (van Herk / Gil-Werman) is a chain of dependent maxima. A
// maximum is exact whatever the order it is taken in, so the values are the same as the direct
// maximum's (with no NaN in x: a NaN's maximum depends on the order of the comparisons).
// scratch is resized to twice x's size and reused, so repeated calls allocate nothing.
void WindowMaxima(std::span<const double> x, std::size_t window, std::span<double> maxima,
                  std::vector<double>& scratch);

// One of several windows over the same values: the maxima of every run of `window` values of x
// from `offset` on (maxima[i] = max(x[offset + i], ..., x[offset + i + window - 1]), as many as
// maxima holds and x allows; offset + window <= x.size()).
struct WindowRun {
  std::size_t offset = 0;
  std::size_t window = 1;
  std::span<double> maxima;
};
// WindowMaxima for each of `runs` (in order of non-decreasing window), the same values: the
// passes of pairwise maxima depend only on x, so the ones the windows share (up to the shorter
// window's) run once, over all of x. The detector's two rise windows share all of the shorter's.
void WindowMaxima(std::span<const double> x, std::span<const WindowRun> runs,
                  std::vector<double>& scratch);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_DETECTOR_WINDOW_MAX_H_
