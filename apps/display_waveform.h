#ifndef BOUNCECAL_APPS_DISPLAY_WAVEFORM_H_
#define BOUNCECAL_APPS_DISPLAY_WAVEFORM_H_

#include <filesystem>

#include "plot/min_max_decimator.h"

namespace bouncecal::apps {

// One channel of a recording as a figure draws it: high-passed at high_pass_hz (first order,
// display only; the detector's own band-pass is sharper) so DC and hum do not hide the impacts,
// and reduced to min/max per pixel column. Re-reads the file in blocks, so memory does not grow
// with the recording's length. Throws InputError for an unreadable file or a channel it lacks.
WaveformColumns DisplayWaveform(const std::filesystem::path& path, int channel, double high_pass_hz,
                                int columns);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_DISPLAY_WAVEFORM_H_
