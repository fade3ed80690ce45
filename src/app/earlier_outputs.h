// A run's outputs may exist already, from an earlier run into the same place. As ffmpeg
// does, `tissu run` and `render` refuse to write over them unless asked to (-y,
// --overwrite), and then remove them before the run writes anything, so that a shorter run
// never leaves the earlier run's last frames beside its own.
#pragma once

#include <string>
#include <vector>

namespace tissu {

// Where a run writes each kind of output; "" for a kind it does not write.
struct RunOutputPaths {
  std::string report;
  std::string mp4;
  std::string png_dir;     // frame_NNNNNN.png
  std::string stills_dir;  // frame_NNNNNN.png
  std::string obj_dir;     // frame_NNNNNN.obj and final.obj
};

// The files of an earlier run among the kinds this run writes: the report and the MP4 if
// they exist, and the files Tissu names in the directories (frame_ and digits, then .png or
// .obj; final.obj). Any other file in those directories is the user's and never counts.
class EarlierOutputs {
 public:
  // Finds them. Throws OutputError ("PATH: cannot write: not a regular file (...)") for one
  // that is not a regular file: such a path is refused with or without --overwrite and
  // never removed (core/output_target.h).
  explicit EarlierOutputs(const RunOutputPaths& paths);

  bool empty() const { return found_.empty(); }
  // Throws OutputError naming the first output found, in one line suggesting -y, e.g.
  // "out/png: holds frames of an earlier run (16 frame_*.png); use -y (--overwrite) to
  // replace them". Does nothing when there is none.
  void refuse() const;
  // Removes every file found; OutputError naming the file that cannot be removed.
  void remove() const;

 private:
  struct Kind {
    std::string place;               // the file, or the directory holding the files
    bool directory = false;
    std::vector<std::string> files;  // sorted
  };
  std::vector<Kind> found_;
};

}  // namespace tissu
