#ifndef BOUNCECAL_AUDIO_SRC_IO_FFMPEG_LIBRARY_H_
#define BOUNCECAL_AUDIO_SRC_IO_FFMPEG_LIBRARY_H_

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/dict.h>
#include <libavutil/error.h>
#include <libavutil/log.h>
#include <libavutil/mathematics.h>
#include <libswresample/swresample.h>
}

#include <string>

namespace bouncecal::audio {

// The FFmpeg functions the decoder calls, resolved from FFmpeg's shared libraries when a file
// first needs them rather than when the program starts. Linked at build time, FFmpeg's four
// libraries and the ~130 they depend on were mapped and relocated by every process: 56 ms of the
// 0.7 s a 10-minute analysis takes, and most of a short `bouncecal` run, for the WAV and FLAC
// files that never reach FFmpeg. The libraries are the ones the headers above describe (their
// major version in the soname), so the declarations match what is loaded.
struct FfmpegLibrary {
  decltype(&::av_dict_free) av_dict_free;
  decltype(&::av_dict_set) av_dict_set;
  decltype(&::av_find_best_stream) av_find_best_stream;
  decltype(&::av_frame_alloc) av_frame_alloc;
  decltype(&::av_frame_free) av_frame_free;
  decltype(&::av_frame_unref) av_frame_unref;
  decltype(&::av_log_get_level) av_log_get_level;
  decltype(&::av_log_set_level) av_log_set_level;
  decltype(&::av_packet_alloc) av_packet_alloc;
  decltype(&::av_packet_free) av_packet_free;
  decltype(&::av_packet_get_side_data) av_packet_get_side_data;
  decltype(&::av_packet_unref) av_packet_unref;
  decltype(&::av_read_frame) av_read_frame;
  decltype(&::av_rescale_q) av_rescale_q;
  decltype(&::av_strerror) av_strerror;
  decltype(&::avcodec_alloc_context3) avcodec_alloc_context3;
  decltype(&::avcodec_descriptor_get) avcodec_descriptor_get;
  decltype(&::avcodec_find_decoder) avcodec_find_decoder;
  decltype(&::avcodec_free_context) avcodec_free_context;
  decltype(&::avcodec_get_name) avcodec_get_name;
  decltype(&::avcodec_open2) avcodec_open2;
  decltype(&::avcodec_parameters_to_context) avcodec_parameters_to_context;
  decltype(&::avcodec_receive_frame) avcodec_receive_frame;
  decltype(&::avcodec_send_packet) avcodec_send_packet;
  decltype(&::avformat_close_input) avformat_close_input;
  decltype(&::avformat_find_stream_info) avformat_find_stream_info;
  decltype(&::avformat_open_input) avformat_open_input;
  decltype(&::swr_alloc_set_opts2) swr_alloc_set_opts2;
  decltype(&::swr_convert) swr_convert;
  decltype(&::swr_free) swr_free;
  decltype(&::swr_init) swr_init;
};

// FFmpeg's functions, loaded on the first call (once per process, thread-safe; the libraries stay
// loaded until the process ends). nullptr, with the reason in *why_not, when the libraries or one
// of the functions cannot be loaded (FFmpeg's runtime packages are not installed).
const FfmpegLibrary* LoadFfmpeg(std::string* why_not);

}  // namespace bouncecal::audio

#endif  // BOUNCECAL_AUDIO_SRC_IO_FFMPEG_LIBRARY_H_
