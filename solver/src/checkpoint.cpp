#include "cdm/solver/checkpoint.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {

constexpr char magic[8] = {'C', 'D', 'M', 'C', 'K', 'P', 'T', '\n'};
constexpr std::uint64_t max_payload = std::uint64_t{1} << 36;  // 64 GiB: refuse absurd lengths before allocating

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim, const RunOrigin& origin) {
  // The state goes straight to the file (a large run's state is not held a second time
  // in memory); its length is learnt first by a pass that only counts, and the header's
  // length and checksum are filled in once the body is written.
  OutArchive counter;  // counts only
  sim.save_state(counter);
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw CheckpointError(path + ": cannot open '" + tmp + "' for writing");
    const std::uint32_t version = checkpoint_format_version;
    std::uint64_t len = 0, sum = 0;
    out.write(magic, sizeof magic);
    out.write(reinterpret_cast<const char*>(&version), sizeof version);
    const auto header_at = out.tellp();
    out.write(reinterpret_cast<const char*>(&len), sizeof len);
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    OutArchive body(out);
    body.put(origin.scene_name);
    body.put(origin.scene_text);
    body.put(static_cast<std::uint64_t>(origin.overrides.size()));
    for (const auto& o : origin.overrides) {
      body.put(o.path);
      body.put(o.value);
    }
    body.put(counter.size());  // the state, as a byte array: its length, then its bytes
    const std::uint64_t before = body.size();
    sim.save_state(body);
    if (body.size() - before != counter.size())
      throw CheckpointError(path + ": the state changed size while it was written (" + std::to_string(counter.size()) +
                            " then " + std::to_string(body.size() - before) + " bytes)");
    len = body.size();
    sum = body.checksum();
    out.seekp(header_at);
    out.write(reinterpret_cast<const char*>(&len), sizeof len);
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    out.flush();
    if (!out) throw CheckpointError(path + ": writing '" + tmp + "' failed (disk full?)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);  // atomic on POSIX: the old checkpoint stays until this succeeds
  if (ec) throw CheckpointError(path + ": cannot rename the new checkpoint into place: " + ec.message());
}

CheckpointData read_checkpoint(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw CheckpointError(path + ": is a directory: expected a checkpoint file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError(path + ": cannot open the checkpoint");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::uint64_t>(in.tellg());
  if (size > max_payload + 64) throw CheckpointError(path + ": not a usable checkpoint: larger than any checkpoint");
  in.seekg(0);
  std::vector<char> bytes(size);
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (!in) throw CheckpointError(path + ": reading the checkpoint failed");
  return read_checkpoint_bytes(bytes, path);
}

CheckpointData read_checkpoint_bytes(const std::vector<char>& bytes, const std::string& path) {
  auto refuse = [&](const std::string& why) -> CheckpointError {
    return CheckpointError(path + ": not a usable checkpoint: " + why);
  };
  constexpr std::size_t header = sizeof magic + sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);
  if (bytes.size() < sizeof magic || std::memcmp(bytes.data(), magic, sizeof magic) != 0)
    throw refuse("it does not start with the cdm checkpoint marker");
  if (bytes.size() < header) throw refuse("its header is truncated");
  std::uint32_t version = 0;
  std::uint64_t len = 0, sum = 0;
  std::memcpy(&version, bytes.data() + 8, sizeof version);
  std::memcpy(&len, bytes.data() + 12, sizeof len);
  std::memcpy(&sum, bytes.data() + 20, sizeof sum);
  if (version != checkpoint_format_version)
    throw refuse("format version " + std::to_string(version) + ", this cdm reads version " +
                 std::to_string(checkpoint_format_version));
  const std::uint64_t have = bytes.size() - header;
  if (len != have)
    throw refuse("its header announces " + std::to_string(len) + " bytes of data and the file holds " +
                 std::to_string(have) + " (truncated or corrupted)");
  const char* body = bytes.data() + header;
  if (fnv1a64(body, have) != sum) throw refuse("its checksum does not match (corrupted)");
  CheckpointData d;
  try {
    InArchive a(body, have);
    a.get(d.origin.scene_name);
    a.get(d.origin.scene_text);
    std::uint64_t no = 0;
    a.get(no);
    if (no > 100000) throw ArchiveError("too many overrides");
    for (std::uint64_t k = 0; k < no; ++k) {
      SceneOverride o;
      a.get(o.path);
      a.get(o.value);
      d.origin.overrides.push_back(o);
    }
    a.get(d.state);
    if (!a.done()) throw ArchiveError("it has data after the state");
  } catch (const ArchiveError& e) {
    throw refuse(e.what());
  }
  return d;
}

void restore_checkpoint(const CheckpointData& data, Simulation& sim, const std::string& path) {
  try {
    InArchive a(data.state.data(), data.state.size());
    sim.load_state(a);
  } catch (const ArchiveError& e) {
    throw CheckpointError(path + ": the checkpoint does not fit its scene: " + e.what());
  }
}

}  // namespace cdm
