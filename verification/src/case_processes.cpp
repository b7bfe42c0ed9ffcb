#include "case_processes.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <fcntl.h>
#include <omp.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cdm/solver/io/durable_file.hpp"
#include "cdm/solver/run_guards.hpp"
#include "cdm/solver/scene_loader.hpp"

namespace cdm::verification {

namespace fs = std::filesystem;

namespace {

/// The exit status and the message's start that a failure in a case gives `cdm verify`,
/// as cdm's main gives them when the case runs in its process.
std::pair<int, const char*> status_of(const std::exception& e) {
  if (dynamic_cast<const cdm::OutputError*>(&e)) return {4, "cdm: output error: "};
  if (dynamic_cast<const cdm::SimulationError*>(&e)) return {3, "cdm: the run went unstable and was stopped: "};
  if (dynamic_cast<const cdm::SceneError*>(&e)) return {2, "cdm: error: "};
  return {1, "cdm: error: "};
}

/// A case run in a child process: its lines go to a file in the output folder, printed
/// by the parent once the child is done; its summary comes back through a pipe.
struct Child {
  pid_t pid = -1;
  int summary_fd = -1;
  std::string log_path;
};

/// One line: pass fail worst_ratio wall, then the worst quantity's description.
std::string encode(const Summary& s) {
  std::ostringstream os;
  os.precision(17);
  os << s.pass << ' ' << s.fail << ' ' << s.worst_ratio << ' ' << s.wall << ' ' << s.worst << '\n';
  return os.str();
}

Child start_case(const std::string& dir, const VerifyOptions& opt, int threads) {
  Child c;
  c.log_path = (fs::path(opt.out_dir) / (fs::path(dir).filename().string() + ".log.tmp")).string();
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(std::string("cdm verify: pipe: ") + std::strerror(errno));
  std::cout << std::flush;
  std::cerr << std::flush;
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("cdm verify: fork: ") + std::strerror(errno));
  if (pid == 0) {
    close(fds[0]);
    int rc = 0;
    try {
      const int log = open(c.log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (log < 0 || dup2(log, STDOUT_FILENO) < 0) cdm::throw_output_error(c.log_path, "open for writing", errno);
      close(log);
      omp_set_num_threads(threads);
      const Summary s = run_case(dir, opt);
      std::cout << std::flush;
      if (!std::cout) cdm::throw_output_error(c.log_path, "write", EIO);
      const std::string line = encode(s);
      if (write(fds[1], line.data(), line.size()) != static_cast<ssize_t>(line.size())) rc = 1;
    } catch (const std::exception& e) {
      const auto [status, prefix] = status_of(e);
      std::cerr << prefix << e.what() << "\n" << std::flush;
      rc = status;
    }
    std::cout << std::flush;
    _exit(rc);
  }
  close(fds[1]);
  c.pid = pid;
  c.summary_fd = fds[0];
  return c;
}

/// The summary of the finished @p c (exit status @p ws), after printing its lines. A case
/// that did not run to its end sets @p status to the child's exit status.
Summary finish_case(const Child& c, int ws, const std::string& name, int& status) {
  std::string line;
  char buf[4096];
  ssize_t n;
  while ((n = read(c.summary_fd, buf, sizeof buf)) > 0) line.append(buf, static_cast<std::size_t>(n));
  close(c.summary_fd);
  {
    std::ifstream log(c.log_path);
    std::cout << log.rdbuf() << std::flush;
  }
  std::error_code ec;
  fs::remove(c.log_path, ec);
  Summary s;
  s.name = name;
  std::istringstream is(line);
  const bool ok = WIFEXITED(ws) && WEXITSTATUS(ws) == 0 && (is >> s.pass >> s.fail >> s.worst_ratio >> s.wall);
  if (!ok) {
    if (status == 0) status = WIFEXITED(ws) && WEXITSTATUS(ws) != 0 ? WEXITSTATUS(ws) : 1;
    if (WIFSIGNALED(ws))
      std::cerr << "cdm verify: " << name << ": the process running it was killed by signal " << WTERMSIG(ws) << "\n";
    return s;
  }
  std::getline(is >> std::ws, s.worst);
  return s;
}

}  // namespace

std::vector<Summary> run_cases_in_processes(const std::vector<std::string>& dirs, const VerifyOptions& opt, int jobs,
                                            int& status) {
  std::vector<Summary> summaries(dirs.size());
  // Up to `jobs` cases at once, each in its own process on its share of the cores;
  // their lines are printed in case order.
  const int threads = std::max(1, omp_get_num_procs() / jobs);
  std::vector<Child> running(dirs.size());
  std::vector<int> exit_status(dirs.size(), -1);  // -1: not finished
  std::size_t next = 0, printed = 0;
  int active = 0;
  while (printed < next || (next < dirs.size() && status == 0)) {
    while (active < jobs && next < dirs.size() && status == 0) {
      running[next] = start_case(dirs[next], opt, threads);
      ++next;
      ++active;
    }
    int ws = 0;
    const pid_t pid = waitpid(-1, &ws, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("cdm verify: waitpid: ") + std::strerror(errno));
    }
    for (std::size_t i = printed; i < next; ++i)
      if (running[i].pid == pid) {
        exit_status[i] = ws;
        --active;
      }
    // The finished cases' lines, in case order.
    for (; printed < next && exit_status[printed] >= 0; ++printed) {
      summaries[printed] =
          finish_case(running[printed], exit_status[printed], fs::path(dirs[printed]).filename().string(), status);
    }
  }
  return summaries;
}

}  // namespace cdm::verification
