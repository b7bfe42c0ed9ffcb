#include "cdm/solver/checkpoint.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/io/durable_file.hpp"
#include "cdm/solver/mpi_session.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {

constexpr char magic[8] = {'C', 'D', 'M', 'C', 'K', 'P', 'T', '\n'};
constexpr std::uint64_t max_payload = std::uint64_t{1} << 36;  // 64 GiB: refuse absurd lengths before allocating

}  // namespace

namespace {

/// outlets.dat's length (format 6), after the other marks.
void put_population_mark(OutArchive& a, const std::optional<std::uint64_t>& m) {
  a.put(static_cast<std::uint8_t>(m ? 1 : 0));
  a.put(m.value_or(0));
}

std::optional<std::uint64_t> get_population_mark(InArchive& a) {
  std::uint8_t has = 0;
  std::uint64_t bytes = 0;
  a.get(has);
  a.get(bytes);
  if (has > 1) throw ArchiveError("its output record is corrupted");
  return has ? std::optional<std::uint64_t>(bytes) : std::nullopt;
}

void put_marks(OutArchive& a, const OutputMarks& m) {
  a.put(static_cast<std::uint8_t>(m.particle_table ? 1 : 0));
  a.put(m.particle_table.value_or(0));
  a.put(static_cast<std::uint8_t>(m.vtk ? 1 : 0));
  const VtkMark v = m.vtk.value_or(VtkMark{});
  a.put(v.last);
  a.put(v.particle_frames);
  a.put(v.gas_frames);
  a.put(static_cast<std::uint8_t>(m.log ? 1 : 0));
  a.put(m.log.value_or(0));
  a.put(static_cast<std::uint64_t>(m.monitors.size()));
  for (std::uint64_t b : m.monitors) a.put(b);
  put_population_mark(a, m.population);
}

OutputMarks get_marks(InArchive& a) {
  OutputMarks m;
  std::uint8_t has = 0;
  std::uint64_t bytes = 0;
  a.get(has);
  a.get(bytes);
  if (has > 1) throw ArchiveError("its output record is corrupted");
  if (has) m.particle_table = bytes;
  VtkMark v;
  a.get(has);
  a.get(v.last);
  a.get(v.particle_frames);
  a.get(v.gas_frames);
  if (has > 1 || v.last < -1) throw ArchiveError("its output record is corrupted");
  if (has) m.vtk = v;
  a.get(has);
  a.get(bytes);
  if (has > 1) throw ArchiveError("its output record is corrupted");
  if (has) m.log = bytes;
  std::uint64_t monitors = 0;
  a.get(monitors);
  if (monitors > 4096) throw ArchiveError("its output record is corrupted");
  m.monitors.resize(monitors);
  for (std::uint64_t& b : m.monitors) a.get(b);
  m.population = get_population_mark(a);
  return m;
}

/// Closes the checkpoint's temporary file and removes it unless it was renamed into place.
struct TempFile {
  std::FILE* f = nullptr;
  std::string path;
  bool renamed = false;
  ~TempFile() {
    if (f) std::fclose(f);
    if (!renamed) std::remove(path.c_str());
  }
};

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim, const RunOrigin& origin,
                      const OutputMarks& marks) {
  // The state goes straight to the file (a large run's state is not held a second time
  // in memory); its length is learnt first by a pass that only counts, and the header's
  // length and checksum are filled in once the body is written.
  OutArchive counter;  // counts only
  sim.save_state(counter);
  TempFile tmp{nullptr, path + ".tmp"};
  tmp.f = std::fopen(tmp.path.c_str(), "wb");
  if (!tmp.f) {
    const int err = errno;
    tmp.renamed = true;  // nothing was created
    throw_output_error(tmp.path, "open for writing", err);
  }
  std::FILE* out = tmp.f;
  const std::uint32_t version = checkpoint_format_version;
  std::uint64_t len = 0, sum = 0;
  auto raw = [&](const void* p, std::size_t n) {
    if (std::fwrite(p, 1, n, out) != n) throw_output_error(tmp.path, "write", errno);
  };
  raw(magic, sizeof magic);
  raw(&version, sizeof version);
  const long header_at = std::ftell(out);
  raw(&len, sizeof len);
  raw(&sum, sizeof sum);
  OutArchive body(out);
  sim.stream_shared(body);
  body.put(origin.scene_name);
  body.put(origin.scene_text);
  body.put(static_cast<std::uint64_t>(origin.overrides.size()));
  for (const auto& o : origin.overrides) {
    body.put(o.path);
    body.put(o.value);
  }
  put_marks(body, marks);
  body.put(counter.size());  // the state, as a byte array: its length, then its bytes
  const std::uint64_t before = body.size();
  sim.save_state(body);
  if (body.size() - before != counter.size())
    throw CheckpointError(path + ": the state changed size while it was written (" + std::to_string(counter.size()) +
                          " then " + std::to_string(body.size() - before) + " bytes)");
  if (body.failed()) throw_output_error(tmp.path, "write", body.error());
  // The blocks' checksums follow the body; the header holds the checksum of theirs.
  const std::vector<std::uint64_t> sums = body.block_sums();
  raw(sums.data(), sums.size() * sizeof(std::uint64_t));
  len = body.size();
  sum = fnv1a64(reinterpret_cast<const char*>(sums.data()), sums.size() * sizeof(std::uint64_t));
  if (std::fseek(out, header_at, SEEK_SET) != 0) throw_output_error(tmp.path, "seek in", errno);
  raw(&len, sizeof len);
  raw(&sum, sizeof sum);
  sync_file(out, tmp.path);
  tmp.f = nullptr;
  if (std::fclose(out) != 0) throw_output_error(tmp.path, "close", errno);
  // Atomic on POSIX: the old checkpoint stays until this succeeds.
  if (std::rename(tmp.path.c_str(), path.c_str()) != 0) throw_output_error(path, "rename '" + tmp.path + "' onto", errno);
  tmp.renamed = true;
  sync_directory(std::filesystem::path(path).parent_path().string());
}

namespace {

constexpr std::size_t header_bytes = sizeof magic + sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);

/// The refusal of the checkpoint at @p path, for the reason @p why.
CheckpointError unusable(const std::string& path, const std::string& why) {
  return CheckpointError(path + ": not a usable checkpoint: " + why);
}

/// The header's checks; its body's length and the checksum of its blocks' checksums,
/// from @p head (the file's first min(header_bytes, its size) bytes) and the file's @p size.
std::pair<std::uint64_t, std::uint64_t> check_header(const char* head, std::uint64_t size, const std::string& path) {
  if (size < sizeof magic || std::memcmp(head, magic, sizeof magic) != 0)
    throw unusable(path, "it does not start with the cdm checkpoint marker");
  if (size < header_bytes) throw unusable(path, "its header is truncated");
  std::uint32_t version = 0;
  std::uint64_t len = 0, sum = 0;
  std::memcpy(&version, head + 8, sizeof version);
  std::memcpy(&len, head + 12, sizeof len);
  std::memcpy(&sum, head + 20, sizeof sum);
  if (version != checkpoint_format_version)
    throw unusable(path, "format version " + std::to_string(version) + ", this cdm reads version " +
                             std::to_string(checkpoint_format_version));
  const std::uint64_t have = size - header_bytes;
  if (len > have || have - len != BlockSums::blocks(len) * sizeof(std::uint64_t))
    throw unusable(path, "its header announces " + std::to_string(len) + " bytes of data and " +
                             std::to_string(BlockSums::blocks(std::min(len, have))) +
                             " block checksums, and the file holds " + std::to_string(have) +
                             " bytes after the header (truncated or corrupted)");
  return {len, sum};
}

/// The checksums of the body's blocks from @p table (the bytes after the body), checked
/// against the header's @p sum.
BlockSums block_sums(const char* table, std::uint64_t len, std::uint64_t sum, const std::string& path) {
  BlockSums b{header_bytes, len, std::vector<std::uint64_t>(BlockSums::blocks(len))};
  const std::size_t bytes = b.sums.size() * sizeof(std::uint64_t);
  if (bytes) std::memcpy(b.sums.data(), table, bytes);
  if (fnv1a64(table, bytes) != sum) throw unusable(path, "its checksum does not match (corrupted): its blocks' table");
  return b;
}

/// Why @p path is refused, from its archive's error @p e (a block that does not match its
/// checksum, or data that does not hold together).
CheckpointError refusal(const std::string& path, const ArchiveError& e) {
  if (dynamic_cast<const ArchiveCorrupt*>(&e))
    return unusable(path, std::string("its checksum does not match (corrupted): ") + e.what());
  return unusable(path, e.what());
}

/// Reads the body's origin and output marks into @p d, then the state's length, which
/// must be exactly what is left: @p a then stands at the state's first byte.
void read_head(InArchive& a, CheckpointData& d) {
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
  d.outputs = get_marks(a);
  std::uint64_t n = 0;
  a.get(n);
  if (n > a.remaining())
    throw ArchiveError("an array's length (" + std::to_string(n) + ") does not fit the data that follows");
  if (n < a.remaining()) throw ArchiveError("it has data after the state");
}

}  // namespace

CheckpointData read_checkpoint(const std::string& path, WorldPlace world) {
  if (std::filesystem::is_directory(path)) throw CheckpointError(path + ": is a directory: expected a checkpoint file");
  // The file stays open and the state is read from it into the simulation's arrays
  // (restore_checkpoint), never held whole: each process reads, and checks, the blocks
  // that hold what it keeps.
  std::shared_ptr<std::FILE> file(std::fopen(path.c_str(), "rb"), [](std::FILE* f) {
    if (f) std::fclose(f);
  });
  std::FILE* const f = file.get();
  if (!f) throw CheckpointError(path + ": cannot open the checkpoint");
  const auto failed = [&] { return CheckpointError(path + ": reading the checkpoint failed"); };
  if (fseeko(f, 0, SEEK_END) != 0) throw failed();
  const off_t end = ftello(f);
  if (end < 0 || fseeko(f, 0, SEEK_SET) != 0) throw failed();
  const auto size = static_cast<std::uint64_t>(end);
  if (size > max_payload + 64) throw unusable(path, "larger than any checkpoint");
  char head[header_bytes] = {};
  const auto head_size = static_cast<std::size_t>(std::min<std::uint64_t>(size, header_bytes));
  if (std::fread(head, 1, head_size, f) != head_size) throw failed();
  const auto [len, sum] = check_header(head, size, path);
  std::vector<char> table(static_cast<std::size_t>(size - header_bytes - len));
  if (fseeko(f, static_cast<off_t>(header_bytes + len), SEEK_SET) != 0 ||
      std::fread(table.data(), 1, table.size(), f) != table.size())
    throw failed();
  CheckpointData d;
  d.blocks = block_sums(table.data(), len, sum, path);
  try {
    InArchive a(f, d.blocks, 0, len);
    read_head(a, d);
    d.state_size = a.remaining();
  } catch (const ArchiveError& e) {
    throw refusal(path, e);
  }
  d.state_at = len - d.state_size;
  // Each process reads, and checks, the blocks that hold its share as it restores it.
  // Among several, every block is checked first, each process a share of them, so that a
  // corrupted block refuses the checkpoint on every process before any restores (and then
  // writes) anything.
  if (world.size > 1) {
    const std::uint64_t blocks = d.blocks.sums.size(), rank = static_cast<std::uint64_t>(world.rank),
                        size = static_cast<std::uint64_t>(world.size);
    const std::uint64_t first = std::min(len, blocks * rank / size * checksum_block),
                        last = std::min(len, blocks * (rank + 1) / size * checksum_block);
    std::string failure;
    try {
      InArchive a(f, d.blocks, first, last - first);
      std::vector<char> scratch(checksum_block);
      for (std::uint64_t left = last - first; left > 0;) {
        const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(left, scratch.size()));
        a.get_values(scratch.data(), k);
        left -= k;
      }
    } catch (const ArchiveError& e) {
      failure = refusal(path, e).what();
    }
    failure = first_failure(failure);
    if (!failure.empty()) throw CheckpointError(failure);
  }
  d.file = std::move(file);
  return d;
}

void send_checkpoint_state(const Simulation& sim) {
  OutArchive part;  // counts only: the writer gathers this process's particles and planes from it
  sim.stream_shared(part);
  sim.save_state(part);
}

CheckpointData read_checkpoint_bytes(const std::vector<char>& bytes, const std::string& path) {
  const auto [len, sum] = check_header(bytes.data(), bytes.size(), path);
  const char* body = bytes.data() + header_bytes;
  const BlockSums blocks = block_sums(body + len, len, sum, path);
  CheckpointData d;
  try {
    for (std::uint64_t b = 0; b < blocks.sums.size(); ++b) blocks.check(b, body + b * checksum_block);
    InArchive a(body, len);
    read_head(a, d);
    d.state.assign(body + (len - a.remaining()), body + len);
  } catch (const ArchiveError& e) {
    throw refusal(path, e);
  }
  return d;
}

namespace {

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

/// The restored state holds finite numbers only (a scene's are checked when it is read).
void check_finite(const Simulation& sim, const std::string& path) {
  auto refuse = [&](const std::string& what) { throw unusable(path, what + " (a run never writes one)"); };
  // Each process checks the particles it counts (each its share among processes).
  const ParticleStore& p = sim.local_particles();
  std::vector<std::uint8_t> counted(p.size(), 0);
  for (const auto& [i0, i1] : sim.counted_runs()) std::fill(counted.begin() + i0, counted.begin() + i1, 1);
  const std::pair<const char*, const std::vector<double>*> fields[] = {
      {"x", &p.x}, {"y", &p.y}, {"z", &p.z}, {"vx", &p.vx}, {"vy", &p.vy}, {"vz", &p.vz},
      {"wx", &p.wx}, {"wy", &p.wy}, {"wz", &p.wz}};
  const IdentityOrder order(p);
  for (std::size_t k = 0; k < p.size(); ++k) {
    const std::size_t i = order.slot_of(k);
    if (!counted[i]) continue;
    for (const auto& [name, v] : fields)
      if (i < v->size() && !std::isfinite((*v)[i]))
        refuse("particle " + std::to_string(k) + " has " + name + " = " + number((*v)[i]));
  }
  if (const fluid::GasField* g = sim.gas()) {
    const std::pair<const char*, const std::vector<double>*> gas[] = {
        {"u", &g->u}, {"v", &g->v}, {"w", &g->w}, {"p", &g->p}, {"eps_g", &g->eps_g}};
    for (const auto& [name, v] : gas)
      for (double x : *v)
        if (!std::isfinite(x)) refuse("the gas field " + std::string(name) + " holds " + number(x));
  }
}

}  // namespace

void restore_checkpoint(const CheckpointData& data, Simulation& sim, const std::string& path) {
  try {
    // The state opens with the particle count, the step count and the time: the time
    // must be the one the run reaches after that many steps (it advances as steps * dt).
    // The state's bytes, in memory or in the checkpoint's file from where they start.
    std::optional<InArchive> a;
    if (data.file) a.emplace(data.file.get(), data.blocks, data.state_at, data.state_size);
    else a.emplace(data.state.data(), data.state.size());
    std::uint64_t n = 0, steps = 0;
    double t = 0.0;
    a->get(n);
    a->get(steps);
    a->get(t);
    if (!std::isfinite(t))
      throw unusable(path, "its time is " + number(t) + ", not a finite number");
    const double expected = static_cast<double>(steps) * sim.dt();
    if (t != expected)
      throw unusable(path, "its time t = " + number(t) + " s is not what its " + std::to_string(steps) +
                               " steps of dt = " + number(sim.dt()) + " s give (" + number(expected) + " s)");
    a->rewind();
    sim.load_state(*a);
  } catch (const ArchiveCorrupt& e) {
    throw refusal(path, e);
  } catch (const ArchiveError& e) {
    throw CheckpointError(path + ": the checkpoint does not fit its scene: " + e.what());
  }
  check_finite(sim, path);
}

}  // namespace cdm
