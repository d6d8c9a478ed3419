#include "core/loop/loop_model.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <glog/logging.h>

#include "core/base/atomic_file.h"
#include "core/fields/field_io.h"
#include "core/base/input_error.h"
#include "core/io/ply_io.h"

namespace es {
namespace {

namespace fs = std::filesystem;

constexpr char kCanonicalFile[] = "canonical.ply";
constexpr char kLoopFile[] = "loop.txt";
constexpr char kMotionFile[] = "motion_field.bin";
constexpr char kResidualFile[] = "residual_field.bin";

std::string Join(const std::string& dir, const char* name) {
  return (fs::path(dir) / name).string();
}

void WriteLoopFile(const LoopModel& model, const std::string& path) {
  std::ostringstream out;
  out << "cycle_length " << model.cycle_length << "\n";
  out << "num_dynamic " << model.num_dynamic() << "\n";
  for (int k = 0; k < model.num_dynamic(); ++k)
    out << model.dynamic_index[k] << " " << model.start_times[k] << "\n";
  WriteTextFileAtomically(path, out.str());
}

// Reads "<key> <int>" from the stream or throws naming the file.
int ReadKeyedInt(std::istream& in, const char* key, const std::string& path) {
  std::string word;
  long long value;
  if (!(in >> word >> value) || word != key)
    throw InputError(path + ": expected '" + key + " <integer>'");
  if (value < 0 || value > (1 << 30))
    throw InputError(path + ": " + key + " out of range");
  return static_cast<int>(value);
}

void ReadLoopFile(const std::string& path, int num_gaussians,
                  LoopModel* model) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open loop file");
  model->cycle_length = ReadKeyedInt(in, "cycle_length", path);
  if (model->cycle_length < 1)
    throw InputError(path + ": cycle_length must be at least 1");
  const int count = ReadKeyedInt(in, "num_dynamic", path);
  if (count > num_gaussians)
    throw InputError(path + ": num_dynamic " + std::to_string(count) +
                     " exceeds the " + std::to_string(num_gaussians) +
                     " Gaussians of " + kCanonicalFile);
  model->dynamic_index.resize(count);
  model->start_times.resize(count);
  for (int k = 0; k < count; ++k) {
    long long index, start;
    if (!(in >> index >> start))
      throw InputError(path + ": expected " + std::to_string(count) +
                       " '<index> <start time>' lines, got " +
                       std::to_string(k));
    if (index < 0 || index >= num_gaussians)
      throw InputError(path + ": Gaussian index " + std::to_string(index) +
                       " out of range");
    if (k > 0 && index <= model->dynamic_index[k - 1])
      throw InputError(path + ": Gaussian indices not ascending at line " +
                       std::to_string(k + 3));
    if (start < 0 || start >= model->cycle_length)
      throw InputError(path + ": start time " + std::to_string(start) +
                       " outside [0, cycle_length)");
    model->dynamic_index[k] = static_cast<int>(index);
    model->start_times[k] = static_cast<int>(start);
  }
  std::string extra;
  if (in >> extra) throw InputError(path + ": unexpected trailing content");
}

}  // namespace

LoopStructure LoopStructure::Of(const LoopModel& model) {
  LoopStructure s;
  s.count = model.gaussians.size();
  s.sh_degree = model.gaussians.sh_degree;
  s.dynamic_index = &model.dynamic_index;
  s.start_times = &model.start_times;
  s.cycle_length = model.cycle_length;
  s.motion = model.motion ? &*model.motion : nullptr;
  s.residual = model.residual ? &*model.residual : nullptr;
  return s;
}

void SaveLoopModel(const LoopModel& model, const std::string& dir) {
  CHECK_EQ(model.dynamic_index.size(), model.start_times.size());
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(dir + ": cannot create directory");
  const std::string ply = Join(dir, kCanonicalFile);
  WritePly(model.gaussians, ply);  // atomic on its own
  WriteLoopFile(model, Join(dir, kLoopFile));
  // A field the model lacks must not be picked up from an earlier save.
  const std::string motion = Join(dir, kMotionFile);
  const std::string residual = Join(dir, kResidualFile);
  if (model.motion) {
    SaveMotionField(*model.motion, motion);
  } else {
    fs::remove(motion, error);
  }
  if (model.residual) {
    SaveResidualField(*model.residual, residual);
  } else {
    fs::remove(residual, error);
  }
}

LoopModel LoadLoopModel(const std::string& dir) {
  LoopModel model;
  model.gaussians = ReadPly(Join(dir, kCanonicalFile));
  ReadLoopFile(Join(dir, kLoopFile), model.gaussians.size(), &model);
  const std::string motion = Join(dir, kMotionFile);
  const std::string residual = Join(dir, kResidualFile);
  if (fs::exists(motion)) model.motion.emplace(LoadMotionField(motion));
  if (fs::exists(residual)) {
    model.residual.emplace(LoadResidualField(residual));
    if (model.residual->options().cycle_length != model.cycle_length)
      throw InputError(residual + ": cycle length " +
                       std::to_string(model.residual->options().cycle_length) +
                       " disagrees with " + kLoopFile + " (" +
                       std::to_string(model.cycle_length) + ")");
  }
  return model;
}

}  // namespace es
