// The ParaView files of one run (docs/contract.md): their names, the series of frames, the
// collections. The files' contents are vtk_writer.h's (elastic bodies, contacts) and body_shapes.h's
// (the other bodies' shapes, output.shapes).
//
// A frame is written by a thread of the series' own: write_frame copies what the frame shows (each
// elastic body's displacement and velocity, the contacts) and returns; the thread computes the
// element fields (stresses: for the frames written only), encodes and writes the files, so that the
// run's steps go on meanwhile. At most kQueuedFrames frames wait; a run that outpaces its writer waits
// for it. The files do not depend on the timing: each frame's are fixed when write_frame is called.
#pragma once

#include "tools/output/body_shapes.h"
#include "tools/output/element_fields.h"
#include "tools/output/vtk_writer.h"
#include "engine/state.h"
#include "engine/world.h"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace csim {

// True when the world holds at least one finite-element body: only such scenes get ParaView files.
bool has_elastic_bodies(const World& world);

// What stops the ParaView files of `world` from being written when a series has `frames` frames: an
// elastic body whose file names would be those of another series (two names that differ only in
// characters outside [A-Za-z0-9_.-], a body named "contacts", or "bodies" when the shapes' series is
// written: `shapes`), or a file name longer than a folder entry may be (NAME_MAX, 255 bytes). Checked
// before the first step (check_outputs in run.h), so that validate refuses what run would.
struct ParaviewNameProblem {
  std::string body;     // the body's name in the scene
  std::string message;  // what is wrong, without the body's name
};
std::optional<ParaviewNameProblem> paraview_name_problem(const World& world, std::size_t frames, bool shapes = false);

// Deletes the ParaView files of an earlier run in DIR/paraview (*.vtu, *.vtp, *.pvd, *.tmp), and the folder
// when that leaves it empty, so that a new run never mixes its frames with stale ones.
void remove_paraview_outputs(const std::string& output_directory);

// The ParaView files of one run. Frames are written as they come; finish() writes the collections.
// A series destroyed before finish() (a stop request, an error of the writer) deletes the frames it
// wrote; a run stopped by a numerical failure calls finish() to keep the frames up to it (run.h). An error of the writer (std::runtime_error naming the file on an I/O error,
// FemError from the element fields) is thrown by the next write_frame, wait() or finish().
class ParaviewSeries {
 public:
  // contact_action: what the contacts' files give of the contacts' action (vtk_writer.h). The elastic
  // bodies' and the contacts' series are written when the world has an elastic body; the shapes'
  // series (body_shapes.h) when `shapes` is true.
  ParaviewSeries(const World& world, const std::string& output_directory, VtkEncoding encoding,
                 const ContactAction& contact_action = {}, bool shapes = false);
  ~ParaviewSeries();
  ParaviewSeries(const ParaviewSeries&) = delete;
  ParaviewSeries& operator=(const ParaviewSeries&) = delete;

  // One frame of every series (elastic bodies, contacts, shapes), at time t (s). `world` must be the one the
  // series was made for, and outlive it.
  void write_frame(const World& world, const State& state, double t);
  // Returns when every frame given so far is on disk.
  void wait();
  void finish();

  static constexpr std::size_t kQueuedFrames = 8;

 private:
  enum class Kind { elastic_body, contacts, shapes };
  struct Series {
    Kind kind = Kind::contacts;
    int body = -1;      // index in World::bodies of an elastic body's series; −1 for the others
    std::string stem;   // file-name prefix
    const char* extension = ".vtu";
    std::optional<EncodedMesh> mesh;  // the body's; none for the contacts
    std::vector<std::string> written;
    std::optional<ElementFieldsSeries> fields;  // the body's stresses (and strains); none for the contacts
  };
  // What one frame shows, copied from the state.
  struct Frame {
    std::size_t index = 0;
    double t = 0.0;                                               // s
    std::vector<Eigen::VectorXd> displacement, velocity;         // m, m/s: every mesh dof, per body series
    std::vector<ActiveContact> contacts;
    BodyShapes::Sample shapes;                                    // when shapes_ is set
  };
  void write_files(const Frame& frame);  // on the writer thread
  void writer_loop();
  void stop_writer(bool discard);

  const World& world_;
  std::string directory_;    // DIR/paraview
  VtkEncoding encoding_;
  ContactAction contact_action_;
  std::vector<Series> series_;  // the elastic bodies, then the contacts, then the shapes
  bool contacts_ = false;               // the contacts' series is written (a world with an elastic body)
  std::optional<BodyShapes> shapes_;    // the shapes' series (output.shapes)
  std::vector<double> times_;   // s, one per frame
  bool finished_ = false;

  std::mutex mutex_;                 // guards the queue, busy_, stopping_ and error_
  std::condition_variable changed_;  // a frame queued or written, an error, a stop
  std::deque<Frame> queue_;
  bool busy_ = false;                // the writer holds a frame
  bool stopping_ = false;
  std::exception_ptr error_;
  std::thread writer_;
};

}  // namespace csim
