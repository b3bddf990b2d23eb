#include "tools/output/paraview_series.h"

#include "engine/bodies/fe_body.h"
#include "tools/output/atomic_file.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <ostream>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace csim {

namespace {

// A body name as a file-name prefix: characters outside [A-Za-z0-9_.-] become '_'.
std::string file_stem(const std::string& name) {
  std::string stem = name.empty() ? "_" : name;
  for (char& c : stem)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) c = '_';
  return stem;
}

std::string frame_name(const std::string& stem, std::size_t frame, const char* extension = ".vtu") {
  char number[32];
  std::snprintf(number, sizeof number, "_%06zu", frame);
  return stem + number + extension;
}

const char* const kShapesStem = "bodies";  // the shapes' series: bodies_NNNNNN.vtp, bodies.pvd

// The longest name a folder entry may have on Linux (NAME_MAX); a longer one fails at open().
constexpr std::size_t kNameMax = 255;
const char* const kTemporarySuffix = ".tmp";  // write_file_atomically's

}  // namespace

bool has_elastic_bodies(const World& world) {
  for (const BodyInstance& b : world.bodies)
    if (b.body->finite_elements()) return true;
  return false;
}

void remove_paraview_outputs(const std::string& output_directory) {
  const std::filesystem::path folder = std::filesystem::path(output_directory) / "paraview";
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) return;
  std::vector<std::filesystem::path> ours;  // listed first: removing while iterating is unspecified
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string extension = entry.path().extension().string();
    if (extension == ".vtu" || extension == ".vtp" || extension == ".pvd" || extension == ".tmp")
      ours.push_back(entry.path());
  }
  for (const auto& path : ours) std::filesystem::remove(path, error);
  std::filesystem::remove(folder, error);  // only succeeds when empty: files of the user's stay
}

std::optional<ParaviewNameProblem> paraview_name_problem(const World& world, std::size_t frames, bool shapes) {
  std::map<std::string, std::string> owners{{"contacts", "the contacts' series"}};  // stem -> whose
  if (shapes) owners.emplace(kShapesStem, "the shapes' series (output.shapes)");
  for (const BodyInstance& b : world.bodies) {
    if (!b.body->finite_elements()) continue;
    const std::string stem = file_stem(b.name);
    const auto [owner, added] = owners.emplace(stem, "body '" + b.name + "'");
    if (!added)
      return ParaviewNameProblem{b.name, "its ParaView files would be named like those of " + owner->second + " (" +
                                             stem + "_*.vtu): rename one of them"};
    const std::string longest = frame_name(stem, frames > 0 ? frames - 1 : 0) + kTemporarySuffix;
    if (longest.size() > kNameMax)
      return ParaviewNameProblem{b.name, "the name is too long for its ParaView files (" + longest.substr(0, 12) +
                                             "..." + longest.substr(longest.size() - 19) + ": " +
                                             std::to_string(longest.size()) + " bytes, at most " +
                                             std::to_string(kNameMax) + "): shorten it"};
  }
  return std::nullopt;
}

ParaviewSeries::ParaviewSeries(const World& world, const std::string& output_directory, VtkEncoding encoding,
                               const ContactAction& contact_action, bool shapes)
    : world_(world), directory_((std::filesystem::path(output_directory) / "paraview").string()), encoding_(encoding),
      contact_action_(contact_action) {
  // The caller has checked the names (check_outputs); this is what a series cannot be written without.
  if (const auto problem = paraview_name_problem(world, 0, shapes))
    throw std::runtime_error(directory_ + ": body '" + problem->body + "': " + problem->message);
  for (std::size_t i = 0; i < world.bodies.size(); ++i)
    if (const FeBody* body = world.bodies[i].body->finite_elements())
      series_.push_back({Kind::elastic_body, static_cast<int>(i), file_stem(world.bodies[i].name), ".vtu",
                         encode_mesh(body->mesh(), encoding), {}, ElementFieldsSeries(*body)});
  contacts_ = has_elastic_bodies(world);
  if (contacts_) series_.push_back({Kind::contacts, -1, "contacts", ".vtu", {}, {}, {}});
  if (shapes) {
    shapes_.emplace(world, encoding);
    series_.push_back({Kind::shapes, -1, kShapesStem, ".vtp", {}, {}, {}});
  }
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) throw FileWriteError(directory_, "cannot create the folder", error);
  writer_ = std::thread([this] { writer_loop(); });
}

ParaviewSeries::~ParaviewSeries() {
  stop_writer(true);
  if (finished_) return;
  std::error_code ignored;  // a destructor must not throw; what cannot be removed stays
  const std::filesystem::path folder(directory_);
  for (const Series& s : series_) {
    for (const std::string& file : s.written) std::filesystem::remove(folder / file, ignored);
    std::filesystem::remove(folder / (frame_name(s.stem, s.written.size(), s.extension) + kTemporarySuffix),
                            ignored);  // one cut short
    std::filesystem::remove(folder / (s.stem + ".pvd"), ignored);  // finish() may have written some
  }
  std::filesystem::remove(directory_, ignored);
}

void ParaviewSeries::stop_writer(bool discard) {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    if (discard) queue_.clear();
  }
  changed_.notify_all();
  if (writer_.joinable()) writer_.join();
}

void ParaviewSeries::writer_loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    changed_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, and nothing left to write
    Frame frame = std::move(queue_.front());
    queue_.pop_front();
    busy_ = true;
    lock.unlock();
    std::exception_ptr error;
    try {
      write_files(frame);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    busy_ = false;
    if (error) {
      error_ = error;
      queue_.clear();  // the run stops at its next write_frame: later frames are not written
    }
    changed_.notify_all();
  }
}

void ParaviewSeries::write_files(const Frame& frame) {
  std::size_t next_body = 0;
  for (Series& s : series_) {
    const std::string file = frame_name(s.stem, frame.index, s.extension);
    const std::string path = (std::filesystem::path(directory_) / file).string();
    if (s.kind == Kind::contacts) {
      write_file_atomically(path, contacts_vtu(frame.contacts, frame.t, encoding_, contact_action_));
    } else if (s.kind == Kind::shapes) {
      VtkFileText text(encoding_);
      shapes_->write(text, frame.shapes, frame.t);
      write_file_atomically(path, [&text](std::ostream& out) { text.write(out); });
    } else {
      // Streamed: a large body's file is not assembled in memory beside its arrays.
      const Eigen::VectorXd& u = frame.displacement[next_body];
      VtkFileText text(s.mesh->encoding);
      fe_body_file(text, *s.mesh, u, frame.velocity[next_body], (*s.fields)(u), frame.t);
      write_file_atomically(path, [&text](std::ostream& out) { text.write(out); });
      ++next_body;
    }
    s.written.push_back(file);
  }
}

void ParaviewSeries::write_frame(const World& world, const State& state, double t) {
  Frame frame;
  frame.index = times_.size();
  frame.t = t;
  for (const Series& s : series_) {
    if (s.kind != Kind::elastic_body) continue;
    const BodyInstance& b = world.bodies[s.body];
    const FeBody& body = *b.body->finite_elements();  // a series is only opened for a finite-element body
    frame.displacement.push_back(body.full_displacement(state.q.segment(b.position_offset, body.position_size())));
    // v holds the same free dofs as q, so the same expansion gives the velocity of every dof.
    frame.velocity.push_back(body.full_displacement(state.v.segment(b.velocity_offset, body.velocity_size())));
  }
  if (contacts_) frame.contacts = state.contacts;
  if (shapes_) frame.shapes = shapes_->sample(state);
  {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return error_ || queue_.size() < kQueuedFrames; });
    if (error_) std::rethrow_exception(error_);
    queue_.push_back(std::move(frame));
  }
  times_.push_back(t);
  changed_.notify_all();
}

void ParaviewSeries::wait() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return error_ || (queue_.empty() && !busy_); });
  if (error_) std::rethrow_exception(error_);
}

void ParaviewSeries::finish() {
  wait();
  for (const Series& s : series_) {
    std::vector<CollectionEntry> entries;
    for (std::size_t k = 0; k < s.written.size(); ++k) entries.push_back({times_[k], s.written[k]});
    write_file_atomically((std::filesystem::path(directory_) / (s.stem + ".pvd")).string(), pvd_collection(entries));
  }
  finished_ = true;
  stop_writer(false);
}

}  // namespace csim
