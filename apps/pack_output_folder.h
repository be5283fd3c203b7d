#ifndef BOUNCECAL_APPS_PACK_OUTPUT_FOLDER_H_
#define BOUNCECAL_APPS_PACK_OUTPUT_FOLDER_H_

#include <filesystem>
#include <string>

namespace bouncecal::apps {

// Where periodic and interruption checkpoints go, overwritten (atomically) by each.
inline constexpr const char* kCheckpointName = "checkpoint.bcpack";

// The outermost folder of `dir` that does not exist yet (empty when `dir` exists): what a run
// that is refused must remove again to leave nothing behind.
std::filesystem::path FirstMissingFolder(const std::filesystem::path& dir);

// Everything that can stop the outputs from being written is checked before the simulation, so
// a typo in --json does not cost minutes of computing for nothing. Throws OutputError.
void CheckOutputsWritable(const std::filesystem::path& dir, const std::filesystem::path& json);

// A rerun into the same folder would otherwise leave the dumps and plots of the earlier run
// beside the new ones (a shorter run writes fewer dumps, a run without --plot no PNGs), and they
// would be read as this run's. Only pack's own file names go; anything else stays.
void RemoveEarlierOutputs(const std::filesystem::path& dir);

// Removes the temporaries of pack's own outputs left by a run that was killed while writing
// (SIGKILL, a second SIGINT, a crash); those of a live process are left alone.
void RemoveStaleTemporaries(const std::filesystem::path& dir);

// The whole checkpoint file of --resume, read before anything in the output folder changes (it
// may live there). Throws InputError naming the file.
std::string ReadCheckpoint(const std::string& path);

}  // namespace bouncecal::apps

#endif  // BOUNCECAL_APPS_PACK_OUTPUT_FOLDER_H_
