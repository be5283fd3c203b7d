#include "io/ffmpeg_library.h"

extern "C" {
#include <libavutil/macros.h>
}

#include <dlfcn.h>

#include <iterator>
#include <optional>
#include <string>

namespace bouncecal::audio {
namespace {

// The sonames of the libraries this build was compiled against: another major version has
// another ABI.
constexpr const char* kLibraries[] = {"libavutil.so." AV_STRINGIFY(LIBAVUTIL_VERSION_MAJOR),
                                      "libswresample.so." AV_STRINGIFY(LIBSWRESAMPLE_VERSION_MAJOR),
                                      "libavcodec.so." AV_STRINGIFY(LIBAVCODEC_VERSION_MAJOR),
                                      "libavformat.so." AV_STRINGIFY(LIBAVFORMAT_VERSION_MAJOR)};

// Debian's runtime packages of those sonames (libavformat's brings libavcodec and libavutil).
constexpr const char* kRuntimePackages = "libavformat" AV_STRINGIFY(
    LIBAVFORMAT_VERSION_MAJOR) " libswresample" AV_STRINGIFY(LIBSWRESAMPLE_VERSION_MAJOR);

// The loaded library, or why it could not be loaded.
struct Loaded {
  std::optional<FfmpegLibrary> library;
  std::string why_not;
};

// Resolves one function by its own name from the libraries opened so far.
template <typename Function>
bool Resolve(void* const (&handles)[std::size(kLibraries)], const char* name, Function& function,
             std::string& why_not) {
  for (void* handle : handles) {
    if (void* symbol = handle ? dlsym(handle, name) : nullptr) {
      function = reinterpret_cast<Function>(symbol);
      return true;
    }
  }
  why_not = std::string("FFmpeg's libraries lack ") + name + " (another FFmpeg version?)";
  return false;
}

Loaded Load() {
  Loaded loaded;
  void* handles[std::size(kLibraries)] = {};
  for (std::size_t i = 0; i < std::size(kLibraries); ++i) {
    // Never closed: FFmpeg keeps process-wide state (its log level, codec tables) alive.
    handles[i] = dlopen(kLibraries[i], RTLD_NOW | RTLD_LOCAL);
    if (handles[i] == nullptr) {
      const char* error = dlerror();
      loaded.why_not = std::string("FFmpeg's libraries cannot be loaded (") +
                       (error ? error : kLibraries[i]) + "; Debian: apt-get install " +
                       kRuntimePackages + ")";
      return loaded;
    }
  }
  FfmpegLibrary f{};
  std::string& why = loaded.why_not;
#define BOUNCECAL_RESOLVE(name) \
  if (!Resolve(handles, #name, f.name, why)) return loaded
  BOUNCECAL_RESOLVE(av_dict_free);
  BOUNCECAL_RESOLVE(av_dict_set);
  BOUNCECAL_RESOLVE(av_find_best_stream);
  BOUNCECAL_RESOLVE(av_frame_alloc);
  BOUNCECAL_RESOLVE(av_frame_free);
  BOUNCECAL_RESOLVE(av_frame_unref);
  BOUNCECAL_RESOLVE(av_log_get_level);
  BOUNCECAL_RESOLVE(av_log_set_level);
  BOUNCECAL_RESOLVE(av_packet_alloc);
  BOUNCECAL_RESOLVE(av_packet_free);
  BOUNCECAL_RESOLVE(av_packet_get_side_data);
  BOUNCECAL_RESOLVE(av_packet_unref);
  BOUNCECAL_RESOLVE(av_read_frame);
  BOUNCECAL_RESOLVE(av_rescale_q);
  BOUNCECAL_RESOLVE(av_strerror);
  BOUNCECAL_RESOLVE(avcodec_alloc_context3);
  BOUNCECAL_RESOLVE(avcodec_descriptor_get);
  BOUNCECAL_RESOLVE(avcodec_find_decoder);
  BOUNCECAL_RESOLVE(avcodec_free_context);
  BOUNCECAL_RESOLVE(avcodec_get_name);
  BOUNCECAL_RESOLVE(avcodec_open2);
  BOUNCECAL_RESOLVE(avcodec_parameters_to_context);
  BOUNCECAL_RESOLVE(avcodec_receive_frame);
  BOUNCECAL_RESOLVE(avcodec_send_packet);
  BOUNCECAL_RESOLVE(avformat_close_input);
  BOUNCECAL_RESOLVE(avformat_find_stream_info);
  BOUNCECAL_RESOLVE(avformat_open_input);
  BOUNCECAL_RESOLVE(swr_alloc_set_opts2);
  BOUNCECAL_RESOLVE(swr_convert);
  BOUNCECAL_RESOLVE(swr_free);
  BOUNCECAL_RESOLVE(swr_init);
#undef BOUNCECAL_RESOLVE
  loaded.library = f;
  return loaded;
}

}  // namespace

const FfmpegLibrary* LoadFfmpeg(std::string* why_not) {
  // Loaded once and never changed after: the immutable result of the first call.
  static const Loaded loaded = Load();
  if (!loaded.library && why_not) *why_not = loaded.why_not;
  return loaded.library ? &*loaded.library : nullptr;
}

}  // namespace bouncecal::audio
