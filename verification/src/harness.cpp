#include "cdm/verification/harness.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <tuple>
#include <stdexcept>
#include <toml++/toml.h>

#include "cdm/solver/io/durable_file.hpp"
#include "case_processes.hpp"

namespace cdm::verification {

namespace fs = std::filesystem;

double Variant::param(const std::string& key) const {
  auto it = oracle.find(key);
  if (it == oracle.end()) throw std::runtime_error("variant '" + name + "': oracle parameter '" + key + "' missing");
  return it->second;
}

namespace {

/// A table of the verification output, opened for writing; OutputError if it cannot be.
std::FILE* open_output(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) cdm::throw_output_error(path, "open for writing", errno);
  return f;
}

std::string fmt(double v, const char* f = "%.6e") {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

double as_number(const toml::node& n, const std::string& where) {
  if (auto i = n.as_integer()) return static_cast<double>(i->get());
  if (auto f = n.as_floating_point()) return f->get();
  throw std::runtime_error(where + ": expected a number");
}

toml::table parse(const std::string& path) {
  try {
    return toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << path << ": does not parse: " << e.description();
    throw std::runtime_error(os.str());
  }
}

bool match(const Tolerance& t, const std::string& variant, const std::string& integ, double div,
           const std::string& q, const std::string& norm) {
  auto m = [](const std::string& pat, const std::string& v) { return pat == "*" || pat == v; };
  return m(t.variant, variant) && m(t.integrator, integ) && (t.dt_divisor == 0.0 || t.dt_divisor == div) &&
         (t.dt_divisor_below == 0.0 || div < t.dt_divisor_below) &&
         t.quantity == q && t.norm == norm;
}

const Tolerance* find_tol(const std::vector<Tolerance>& tols, const std::string& variant, const std::string& integ,
                          double div, const std::string& q, const std::string& norm) {
  for (const auto& t : tols)
    if (match(t, variant, integ, div, q, norm)) return &t;
  return nullptr;
}

/// Work-precision tables for one case: every run's error against its wall time, and
/// per method the cheapest run that reaches 1 %, 0.1 % and 0.01 % error.
template <class Run>
void write_work_precision(const fs::path& out, const std::string& name, const std::vector<Run>& runs) {
  const std::string path = (out / "work_precision.dat").string();
  std::FILE* f = open_output(path);
  std::fprintf(f, "# cdm verify --sweep: case %s. Percent-error norms only (counts and orders left out).\n", name.c_str());
  std::fprintf(f, "# cheapest: per variant, integrator and quantity, the run of least wall time whose error is <= target;"
                  " not_reached if no run in the sweep gets there\n");
  std::fprintf(f, "# case variant integrator quantity norm target[%%] reached dt_divisor[-] dt[s] error[%%] wall[s] particle_steps[-]\n");
  std::map<std::tuple<std::string, std::string, std::string, std::string>, std::vector<const Run*>> groups;
  for (const auto& r : runs)
    if (r.norm.find("pct") != std::string::npos) groups[{r.variant, r.integ, r.q, r.norm}].push_back(&r);
  for (const auto& [key, list] : groups)
    for (double target : {1.0, 0.1, 0.01}) {
      const Run* best = nullptr;
      for (const Run* r : list)
        if (std::isfinite(r->err) && r->err <= target && (!best || r->wall < best->wall)) best = r;
      const auto& [variant, integ, q, norm] = key;
      if (best)
        std::fprintf(f, "%s %s %s %s %s %g yes %g %.6e %.6e %.6e %llu\n", name.c_str(), variant.c_str(), integ.c_str(),
                     q.c_str(), norm.c_str(), target, best->div, best->dt, best->err, best->wall,
                     static_cast<unsigned long long>(best->psteps));
      else
        std::fprintf(f, "%s %s %s %s %s %g not_reached - - - - -\n", name.c_str(), variant.c_str(), integ.c_str(),
                     q.c_str(), norm.c_str(), target);
    }
  cdm::close_file(f, path);
}

}  // namespace

std::optional<double> observed_order(const std::vector<double>& dt, const std::vector<double>& err) {
  std::vector<double> x, y;
  for (std::size_t k = 0; k < dt.size(); ++k)
    if (err[k] > 0.0 && std::isfinite(err[k])) { x.push_back(std::log(dt[k])); y.push_back(std::log(err[k])); }
  if (x.size() < 2) return std::nullopt;
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) { mx += x[k]; my += y[k]; }
  mx /= x.size(); my /= y.size();
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k) { sxy += (x[k] - mx) * (y[k] - my); sxx += (x[k] - mx) * (x[k] - mx); }
  if (sxx <= 0) return std::nullopt;
  return sxy / sxx;
}

CaseDef load_case(const std::string& dir) {
  const std::string file = (fs::path(dir) / "case.toml").string();
  toml::table t = parse(file);
  CaseDef c;
  c.dir = dir;
  c.name = fs::path(dir).filename().string();
  c.kind = t["kind"].value_or(std::string{});
  c.title = t["title"].value_or(std::string{});
  c.scene = (fs::path(dir) / t["scene"].value_or(std::string{"scene.toml"})).string();
  if (c.kind.empty()) throw std::runtime_error(file + ": key 'kind' missing");
  if (!case_runners().count(c.kind)) throw std::runtime_error(file + ": key 'kind' = \"" + c.kind + "\": no such case runner");
  if (auto s = t["sweep"].as_table()) {
    if (auto a = (*s)["integrators"].as_array())
      for (auto& e : *a) c.integrators.push_back(e.value_or(std::string{}));
    if (auto a = (*s)["dt_divisors"].as_array())
      for (auto& e : *a) c.dt_divisors.push_back(as_number(e, file + ": sweep.dt_divisors"));
    if (auto d = (*s)["divisor"].value<std::string>()) c.divisor_meaning = *d;
  }
  if (auto s = t["sweep"].as_table())
    if (auto a = (*s)["sweep_dt_divisors"].as_array())
      for (auto& e : *a) c.sweep_dt_divisors.push_back(as_number(e, file + ": sweep.sweep_dt_divisors"));
  if (c.sweep_dt_divisors.empty())
    c.sweep_dt_divisors = {12.5, 17.7, 25, 35.4, 50, 70.7, 100, 141, 200, 283, 400, 566, 800, 1131, 1600};
  if (c.integrators.empty() || c.dt_divisors.empty())
    throw std::runtime_error(file + ": [sweep] needs integrators and dt_divisors");
  if (auto o = t["options"].as_table())
    for (auto&& [k, v] : *o) {
      std::ostringstream os;
      if (auto sv = v.as_string()) os << sv->get();
      else os << as_number(v, file + ": options." + std::string(k.str()));
      c.options[std::string(k.str())] = os.str();
    }
  auto vs = t["variants"].as_array();
  if (!vs || vs->empty()) throw std::runtime_error(file + ": needs at least one [[variants]]");
  for (auto& vn : *vs) {
    const toml::table& vt = *vn.as_table();
    Variant v;
    v.name = vt["name"].value_or(std::string{});
    v.scene = vt["scene"] ? (fs::path(dir) / vt["scene"].value_or(std::string{})).string() : c.scene;
    v.family = vt["family"].value_or(std::string{});
    if (auto h = vt.get("h")) v.h = as_number(*h, file + ": variants.h");
    v.sweep_only = vt["sweep_only"].value_or(false);
    if (v.h > 0.0 && v.family.empty()) throw std::runtime_error(file + ": variant '" + v.name + "' has h but no family");
    if (auto a = vt["set"].as_array())
      for (auto& e : *a) v.set.push_back(parse_override(e.value_or(std::string{})));
    if (auto o = vt["oracle"].as_table())
      for (auto&& [k, val] : *o) v.oracle[std::string(k.str())] = as_number(val, file + ": oracle." + std::string(k.str()));
    c.variants.push_back(v);
  }
  return c;
}

std::vector<Tolerance> load_tolerances(const std::string& case_dir) {
  const std::string file = (fs::path(case_dir) / "tolerances.toml").string();
  std::vector<Tolerance> out;
  if (!fs::exists(file)) return out;
  toml::table t = parse(file);
  auto arr = t["tolerance"].as_array();
  if (!arr) return out;
  for (auto& n : *arr) {
    const toml::table& e = *n.as_table();
    Tolerance tol;
    tol.variant = e["variant"].value_or(std::string{"*"});
    tol.integrator = e["integrator"].value_or(std::string{"*"});
    tol.quantity = e["quantity"].value_or(std::string{});
    tol.norm = e["norm"].value_or(std::string{});
    if (auto d = e.get("dt_divisor")) tol.dt_divisor = as_number(*d, file + ": dt_divisor");
    if (auto d = e.get("dt_divisor_below")) tol.dt_divisor_below = as_number(*d, file + ": dt_divisor_below");
    if (auto m = e.get("max")) tol.max = as_number(*m, file + ": max");
    else if (auto m2 = e.get("min_order")) tol.max = as_number(*m2, file + ": min_order");
    else if (auto m3 = e.get("min")) { tol.max = as_number(*m3, file + ": min"); tol.at_least = true; }
    else if (e["report_only"].value_or(false)) tol.report_only = true;
    else throw std::runtime_error(file + ": a [[tolerance]] needs 'max', 'min', 'min_order' or 'report_only = true'");
    if (auto o = e.get("order")) tol.order = as_number(*o, file + ": order");
    if (auto rd = e.get("ref_divisor")) tol.ref_divisor = as_number(*rd, file + ": ref_divisor");
    tol.reason = e["reason"].value_or(std::string{});
    if (tol.quantity.empty() || tol.norm.empty() || tol.reason.empty())
      throw std::runtime_error(file + ": every [[tolerance]] needs quantity, norm and reason");
    out.push_back(tol);
  }
  return out;
}

Summary run_case(const std::string& dir, const VerifyOptions& opt) {
  const std::string name = fs::path(dir).filename().string();
  const CaseDef c = load_case(dir);
  const auto tols = load_tolerances(dir);
  const CaseRunner& runner = case_runners().at(c.kind);
  const fs::path out = fs::path(opt.out_dir) / name;
  cdm::make_output_directory((out / "series").string());
  Summary s;
  s.name = name;
  std::cout << "== " << name << ": " << c.title << "\n";

  struct WpRun { std::string variant, integ, q, norm; double div, dt, err, wall; std::uint64_t psteps; };
  std::vector<WpRun> wp;
  const std::string table_path = (out / (opt.sweep ? "errors_sweep.dat" : "errors.dat")).string();
  std::FILE* tf = open_output(table_path);
  std::fprintf(tf, "# cdm verify: case %s (%s)\n", name.c_str(), c.title.c_str());
  std::fprintf(tf, "# dt_divisor N: %s\n", c.divisor_meaning.c_str());
  std::fprintf(tf, "# errors: norm max_rel_pct = max over the series of 100|Q_oracle - Q|/|Q_oracle| (Garg et al. eq 37);"
                   " order = least-squares slope of log(error) vs log(dt) over the dt sweep\n");
  std::fprintf(tf, "# pass: yes/no against the tolerance in tolerances.toml; info = reported, no tolerance\n");
  std::fprintf(tf, "# wall: solver time of one run (steady clock, oracle excluded), the median of timing_runs runs"
                   " (a run is repeated until %.2f s of solver time has been timed, at most 25 runs)\n", opt.min_timing_seconds);
  std::fprintf(tf, "# case variant integrator dt_divisor[-] dt[s] quantity norm error tolerance pass wall[s] timing_runs[-] steps[-] particle_steps_per_s[1/s] oracle\n");

  auto emit = [&](const std::string& variant, const std::string& integ, const std::string& div, double divisor, double dt,
                  const std::string& q, const std::string& norm, double err, const Tolerance* tol, bool is_order,
                  double wall, std::uint64_t steps, std::uint64_t np, const std::string& oracle, std::size_t runs) {
    std::string pass = "info", tol_s = "-";
    if (tol && tol->report_only) tol = nullptr;
    // The dense sweep also runs coarser than the verified range (t_col/50 and finer):
    // those runs show what accuracy costs and are not held to the tolerances.
    const double min_div = *std::min_element(c.dt_divisors.begin(), c.dt_divisors.end());
    if (tol && !is_order && divisor < min_div) tol = nullptr;
    if (tol) {
      const bool at_least = is_order || tol->at_least;
      const double bound = is_order ? tol->max : tol->at(divisor);
      const bool ok = at_least ? (std::isfinite(err) && err >= bound) : (std::isfinite(err) && err <= bound);
      pass = ok ? "yes" : "no";
      tol_s = (at_least ? ">=" : "") + fmt(bound, "%.3g");
      if (ok) ++s.pass; else ++s.fail;
      const double ratio = at_least ? (err > 0 ? bound / err : INFINITY) : (bound > 0 ? err / bound : (err > 0 ? INFINITY : 0.0));
      if (ratio > s.worst_ratio) {
        s.worst_ratio = ratio;
        s.worst = variant + " " + integ + " dt/" + div + " " + q + " " + norm + " = " + fmt(err, "%.3g") + " (tol " + tol_s + ")";
      }
    }
    const double rate = wall > 0 ? static_cast<double>(steps) * static_cast<double>(np) / wall : 0.0;
    std::fprintf(tf, "%s %s %s %s %s %s %s %.6e %s %s %s %zu %llu %s %s\n", name.c_str(), variant.c_str(), integ.c_str(),
                 div.c_str(), dt > 0 ? fmt(dt).c_str() : "-", q.c_str(), norm.c_str(), err, tol_s.c_str(),
                 pass.c_str(), wall > 0 ? fmt(wall, "%.4e").c_str() : "-", runs, static_cast<unsigned long long>(steps),
                 rate > 0 ? fmt(rate, "%.4e").c_str() : "-", oracle.empty() ? "-" : oracle.c_str());
    if (pass == "no")
      std::cout << "  FAIL " << variant << " " << integ << " dt/" << div << " " << q << " (" << norm
                << ") = " << fmt(err, "%.4g") << ", tolerance " << tol_s << "\n";
  };

  // (family, integrator, divisor, quantity, norm) -> (h, error) for the grid orders.
  std::map<std::tuple<std::string, std::string, double, std::string, std::string>, std::vector<std::pair<double, double>>>
      grid_errs;
  for (const auto& v : c.variants) {
    if (v.sweep_only && !opt.sweep) continue;
    for (const auto& integ : c.integrators) {
      // quantity|norm -> errors per dt, for the observed order.
      std::map<std::pair<std::string, std::string>, std::vector<double>> errs;
      std::vector<double> dts;
      for (double div : opt.sweep ? c.sweep_dt_divisors : c.dt_divisors) {
        char divs[32];
        std::snprintf(divs, sizeof divs, "%g", div);
        RunConfig rc{integ, div, (out / "series" / (v.name + "_" + integ + "_dt" + divs + ".dat")).string()};
        RunOutput r = runner(c, v, rc);
        // Short runs are timed again until 0.2 s of solver time has accumulated (at
        // most 25 runs) and the median is kept, so the wall column is not timer noise.
        std::vector<double> walls{r.wall_seconds};
        double total = r.wall_seconds;
        RunConfig again = rc;
        again.series_path.clear();
        again.timing_only = true;
        while (total < opt.min_timing_seconds && walls.size() < 25) {
          walls.push_back(runner(c, v, again).wall_seconds);
          total += walls.back();
        }
        std::sort(walls.begin(), walls.end());
        r.wall_seconds = walls[walls.size() / 2];
        r.timing_repeats = walls.size();
        s.wall += r.wall_seconds;
        dts.push_back(r.dt);
        for (const auto& m : r.measurements) {
          errs[{m.quantity, m.norm}].push_back(m.error);
          wp.push_back({v.name, integ, m.quantity, m.norm, div, r.dt, m.error, r.wall_seconds, r.steps * r.particles});
          if (v.h > 0.0) grid_errs[{v.family, integ, div, m.quantity, m.norm}].push_back({v.h, m.error});
          emit(v.name, integ, divs, div, r.dt, m.quantity, m.norm, m.error,
               find_tol(tols, v.name, integ, div, m.quantity, m.norm), false, r.wall_seconds, r.steps, r.particles,
               r.oracle_accuracy, r.timing_repeats);
        }
      }
      for (const auto& [qn, e] : errs) {
        if (e.size() != dts.size()) continue;
        auto order = observed_order(dts, e);
        emit(v.name, integ, "all", 0.0, 0.0, qn.first, qn.second + "_order", order ? *order : NAN,
             find_tol(tols, v.name, integ, 0.0, qn.first, qn.second + "_order"), true, 0.0, 0, 0, "", 0);
      }
    }
  }
  // Observed order under grid refinement, per family, integrator and dt divisor.
  for (const auto& [key, he] : grid_errs) {
    if (he.size() < 2) continue;
    const auto& [family, integ, div, q, norm] = key;
    std::vector<double> hs, es;
    for (const auto& [h, e] : he) { hs.push_back(h); es.push_back(e); }
    auto order = observed_order(hs, es);
    char divs[32];
    std::snprintf(divs, sizeof divs, "%g", div);
    const std::string row = family + "_grids";
    emit(row, integ, divs, 0.0, 0.0, q, norm + "_grid_order", order ? *order : NAN,
         find_tol(tols, row, integ, div, q, norm + "_grid_order"), true, 0.0, 0, 0, "", 0);
  }
  cdm::close_file(tf, table_path);
  if (opt.sweep) write_work_precision(out, name, wp);
  std::cout << "  " << s.pass << " passed, " << s.fail << " failed; solver wall time " << fmt(s.wall, "%.3f")
            << " s; table " << table_path << "\n";
  if (!s.worst.empty()) std::cout << "  closest to its tolerance: " << s.worst << "\n";
  return s;
}

int verify(const VerifyOptions& opt) {
  std::vector<std::string> dirs;
  for (const auto& e : fs::directory_iterator(opt.cases_dir))
    if (e.is_directory() && fs::exists(e.path() / "case.toml")) dirs.push_back(e.path().string());
  std::sort(dirs.begin(), dirs.end());
  for (const auto& name : opt.only) {
    const bool found = std::any_of(dirs.begin(), dirs.end(), [&](auto& d) { return fs::path(d).filename() == name; });
    if (!found) {
      std::cerr << "cdm verify: no case '" << name << "' in " << opt.cases_dir << "\n";
      return 2;
    }
  }
  if (!opt.only.empty())
    std::erase_if(dirs, [&](const std::string& d) {
      return std::find(opt.only.begin(), opt.only.end(), fs::path(d).filename().string()) == opt.only.end();
    });
  cdm::make_output_directory(opt.out_dir);

  std::vector<Summary> summaries(dirs.size());
  const auto suite_start = std::chrono::steady_clock::now();
  const int jobs = std::max(1, std::min<int>(opt.jobs, static_cast<int>(dirs.size())));
  int status = 0;
  if (jobs == 1) {
    for (std::size_t i = 0; i < dirs.size(); ++i) summaries[i] = run_case(dirs[i], opt);
  } else {
    summaries = run_cases_in_processes(dirs, opt, jobs, status);
    if (status != 0) return status;
  }

  bool all_ok = true;
  for (const auto& s : summaries) all_ok = all_ok && s.fail == 0;
  const double suite_wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - suite_start).count();
  const std::string summary_path = (fs::path(opt.out_dir) / (opt.sweep ? "summary_sweep.dat" : "summary.dat")).string();
  if (std::FILE* f = open_output(summary_path)) {
    std::fprintf(f, "# cdm verify summary; suite wall time %.3f s (solver and oracles)\n", suite_wall);
    std::fprintf(f, "# case passed[-] failed[-] worst_error_over_tolerance[-] solver_wall[s]\n");
    for (const auto& s : summaries)
      std::fprintf(f, "%s %d %d %.6e %.6e\n", s.name.c_str(), s.pass, s.fail, s.worst_ratio, s.wall);
    cdm::close_file(f, summary_path);
  }
  const std::string prov_path = (fs::path(opt.out_dir) / (opt.sweep ? "provenance_sweep.dat" : "provenance.dat")).string();
  if (std::FILE* f = open_output(prov_path)) {
    std::fprintf(f, "# cdm verify provenance: key value\n");
    for (const auto& [k, v] : opt.provenance) std::fprintf(f, "%s %s\n", k.c_str(), v.c_str());
    std::fprintf(f, "suite_wall_s %.3f\n", suite_wall);
    std::fprintf(f, "cases_at_once %d\n", jobs);
    cdm::close_file(f, prov_path);
  }
  std::cout << "\nSummary (" << fmt(suite_wall, "%.1f") << " s):\n";
  int np = 0, nf = 0;
  for (const auto& s : summaries) {
    std::cout << "  " << (s.fail ? "FAIL " : "pass ") << s.name << ": " << s.pass << " passed, " << s.fail
              << " failed, worst error/tolerance " << fmt(s.worst_ratio, "%.3g") << "\n";
    np += s.pass; nf += s.fail;
  }
  std::cout << np << " passed, " << nf << " failed\n";
  std::cout << "tables under " << opt.out_dir << "\n";
  return all_ok ? 0 : 1;
}

}  // namespace cdm::verification
