/// @file insertions.cpp
/// @brief Size distributions (`radius` or a `size` table, for any block that places
/// particles at random or over time), [[insertions]] and [[outlets]].
#include "sections.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>

namespace cdm::scene {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

std::string number_text(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::vector<double> positive_list(const Reader& rd, const toml::table& t, const std::string& key, const std::string& path,
                                  Dim dim, bool allow_zero) {
  const toml::node* n = t.get(key);
  const std::string what = allow_zero ? "a non-empty array of numbers >= 0" : "a non-empty array of numbers > 0";
  if (!n) rd.fail_missing(join(path, key), what);
  const toml::array* a = n->as_array();
  if (!a || a->empty() || a->size() > 10000) rd.fail_value(join(path, key), *n, what + " (at most 10000)");
  std::vector<double> v;
  for (const auto& e : *a) {
    double x = 0.0;
    if (auto i = e.as_integer()) x = static_cast<double>(i->get());
    else if (auto f = e.as_floating_point()) x = f->get();
    else rd.fail_value(join(path, key), *n, what);
    if (!std::isfinite(x) || x < 0.0 || (!allow_zero && x == 0.0)) rd.fail_value(join(path, key), *n, what);
    v.push_back(x * rd.factor(dim));
  }
  return v;
}

}  // namespace

SizeDistribution read_size(const Reader& rd, const toml::table& t, const std::string& path) {
  SizeDistribution d;
  const toml::table* st = rd.table(t, "size", path, false);
  if (!st) {
    if (!t.get("radius")) rd.fail_missing(path + ".radius", "a radius > 0, or a size distribution table " + path + ".size");
    d.radius = rd.positive(t, "radius", path, Dim::length, true);
    return d;
  }
  if (const toml::node* r = t.get("radius"))
    rd.fail_value(path + ".radius", *r, "no radius when " + path + ".size gives the distribution of the radii");
  const std::string sp = path + ".size";
  const std::string schema_key = path.substr(0, path.find('[')) + "[].size";
  rd.check_keys(*st, schema_key, sp);
  if (!st->get("distribution"))
    rd.fail_missing(sp + ".distribution", keyword_list(size_kind_keywords, [](SizeKind) { return true; }));
  d.kind = rd.keyword(*st, "distribution", sp, size_kind_keywords, SizeKind::discrete);
  d.basis = rd.keyword(*st, "basis", sp, size_basis_keywords, SizeBasis::number);
  const char* keys_of[] = {"radii", "fractions", "mean", "std", "median", "sigma"};
  auto used = [&](SizeKind k, const std::string& key) {
    if (k == SizeKind::discrete) return key == "radii" || key == "fractions";
    if (k == SizeKind::normal) return key == "mean" || key == "std";
    if (k == SizeKind::lognormal) return key == "median" || key == "sigma";
    return false;
  };
  for (const char* k : keys_of)
    if (!used(d.kind, k))
      rd.reject_unused(*st, k, sp, std::string("it belongs to another distribution than \"") +
                                       keyword_of(size_kind_keywords, d.kind) + "\"");
  const double length = rd.factor(Dim::length);
  switch (d.kind) {
    case SizeKind::fixed: break;
    case SizeKind::discrete: {
      rd.reject_unused(*st, "min", sp, "a discrete distribution draws only the listed radii");
      rd.reject_unused(*st, "max", sp, "a discrete distribution draws only the listed radii");
      std::vector<double> radii = positive_list(rd, *st, "radii", sp, Dim::length, false);
      std::vector<double> fractions = positive_list(rd, *st, "fractions", sp, Dim::none, true);
      if (fractions.size() != radii.size())
        rd.fail_value(sp + ".fractions", *st->get("fractions"),
                      "one fraction per radius (" + std::to_string(radii.size()) + " radii, " +
                          std::to_string(fractions.size()) + " fractions)");
      double sum = 0.0;
      for (double f : fractions) sum += f;
      if (!(std::abs(sum - 1.0) <= 1e-6))
        rd.fail_value(sp + ".fractions", *st->get("fractions"),
                      "fractions summing to 1 (within 1e-6); they sum to " + number_text(sum));
      d.set_discrete(std::move(radii), std::move(fractions));
      return d;
    }
    case SizeKind::uniform:
      d.min = rd.positive(*st, "min", sp, Dim::length, true);
      d.max = rd.positive(*st, "max", sp, Dim::length, true);
      break;
    case SizeKind::normal:
      d.mean = rd.positive(*st, "mean", sp, Dim::length, true);
      d.std_dev = rd.positive(*st, "std", sp, Dim::length, true);
      d.min = rd.number(*st, "min", sp, Dim::length).value_or(d.mean - 3.0 * d.std_dev);
      d.max = rd.number(*st, "max", sp, Dim::length).value_or(d.mean + 3.0 * d.std_dev);
      break;
    case SizeKind::lognormal: {
      d.median = rd.positive(*st, "median", sp, Dim::length, true);
      d.sigma = rd.number_in(*st, "sigma", sp, Dim::none, true, 0.0, 0.0, true, 3.0, false, "in (0, 3]");
      const double m = d.number_median();
      d.min = rd.number(*st, "min", sp, Dim::length).value_or(m * std::exp(-3.0 * d.sigma));
      d.max = rd.number(*st, "max", sp, Dim::length).value_or(m * std::exp(3.0 * d.sigma));
      break;
    }
  }
  // The cut-offs: 0 < min < max, keeping a usable share of the distribution.
  if (!(d.min > 0.0)) {
    if (const toml::node* n = st->get("min")) rd.fail_value(sp + ".min", *n, "a smallest radius > 0");
    rd.fail_missing(sp + ".min", "a smallest radius > 0 (the default, 3 standard deviations below the mean, is " +
                                     number_text(d.min / length) + ")");
  }
  if (!(d.max > d.min)) {
    const toml::node* n = st->get("max");
    if (n) rd.fail_value(sp + ".max", *n, "a largest radius above " + sp + ".min (" + number_text(d.min / length) + ")");
    rd.fail_value(sp + ".min", *st->get("min"), "a smallest radius below " + sp + ".max (" + number_text(d.max / length) + ")");
  }
  if (!(d.kept_fraction() >= 1e-3))
    rd.fail_value(sp + (st->get("min") ? ".min" : ".max"), *st->get(st->get("min") ? "min" : "max"),
                  "cut-offs that keep at least 0.1 % of the distribution (they keep " + number_text(d.kept_fraction()) +
                      ")");
  return d;
}

void read_insertions(const Reader& rd, SceneSpec& spec) {
  const toml::array* is = rd.array_of_tables(rd.root(), "insertions");
  if (!is) return;
  for (std::size_t i = 0; i < is->size(); ++i) {
    const toml::table& t = *is->get(i)->as_table();
    const std::string path = "insertions[" + std::to_string(i) + "]";
    rd.check_keys(t, "insertions[]", path);
    if (spec.tracers)
      throw SceneError(rd.file() + ": key '" + path + "' is not used: modules.tracers is true (tracers are placed at "
                       "the start and move with the gas)");
    InsertionSpec in;
    in.key = path;
    in.material = particle_material(rd, spec, t, path);
    if (spec.materials[in.material].fixed)
      rd.fail_value(path + ".material", *t.get("material"), "a material that is not fixed (inserted particles move)");
    in.size = read_size(rd, t, path);
    in.region = read_region(rd, t, path, "insertions[]");
    // The checks below take a cylinder by its bounding box; messages name what was written.
    const Vec3 lo = in.region.lower, hi = in.region.upper;
    const bool cyl = in.region.cylinder;
    const std::string upper_key = path + (cyl ? ".cylinder" : ".upper"), lower_key = path + (cyl ? ".cylinder" : ".lower");
    const toml::node& upper_node = *t.get(cyl ? "cylinder" : "upper");
    const toml::node& lower_node = *t.get(cyl ? "cylinder" : "lower");
    const std::string what = cyl ? "a cylinder whose bounding box lies" : "a box";
    // The rate: a number or a mass per second, exactly one.
    const bool cr = t.get("count_rate") != nullptr, mr = t.get("mass_rate") != nullptr;
    if (cr == mr) {
      if (cr) rd.fail_value(path + ".mass_rate", *t.get("mass_rate"), "either count_rate or mass_rate, not both");
      rd.fail_missing(path + ".count_rate", "a rate: count_rate (particles per second) or mass_rate (kg/s)");
    }
    in.rate_by_mass = mr;
    if (cr) in.rate = rd.positive(t, "count_rate", path, Dim::none, true);
    else in.rate = rd.positive(t, "mass_rate", path, Dim::none, true) * rd.factor(Dim::density) * std::pow(rd.factor(Dim::length), 3);
    // The total: a count or a mass, at most one.
    if (t.get("count") && t.get("mass"))
      rd.fail_value(path + ".mass", *t.get("mass"), "either count or mass as the total, not both");
    if (t.get("count")) in.total = static_cast<double>(particle_count(rd, t, path));
    if (t.get("mass")) {
      in.total_by_mass = true;
      in.total = rd.positive(t, "mass", path, Dim::none, true) * rd.factor(Dim::density) * std::pow(rd.factor(Dim::length), 3);
    }
    in.start = rd.number_in(t, "start", path, Dim::time, false, 0.0, 0.0, false, inf, false, ">= 0");
    in.end = rd.number_in(t, "end", path, Dim::time, false, inf, 0.0, false, inf, false, "> start");
    if (!(in.end > in.start)) rd.fail_value(path + ".end", *t.get("end"), "a time after " + path + ".start");
    if (!(in.start < spec.end_time))
      rd.fail_value(path + ".start", *t.get("start"), "a time before integrator.end_time (" + number_text(spec.end_time) + " s)");
    in.interval = rd.number_in(t, "interval", path, Dim::time, false, 0.0, 0.0, false, inf, false, ">= 0");
    in.velocity = rd.vec3(t, "velocity", path, Dim::velocity).value_or(Vec3{});
    if (const toml::node* sn = t.get("seed")) {
      if (!sn->is_integer() || sn->as_integer()->get() < 0) rd.fail_value(path + ".seed", *sn, "an integer >= 0");
      in.seed = static_cast<std::uint64_t>(sn->as_integer()->get());
    }
    // The particles it may insert, bounded like the placed ones.
    const double duration = std::min(in.end, spec.end_time) - in.start;
    const double d_min = 2.0 * in.size.smallest();
    const double m_min = spec.materials[in.material].density * std::numbers::pi * d_min * d_min * d_min / 6.0;
    double most = in.rate_by_mass ? in.rate * duration / m_min + 1.0 : in.rate * duration + 1.0;
    if (!in.total_by_mass) most = std::min(most, in.total);
    else most = std::min(most, in.total / m_min + 1.0);
    if (!(most <= static_cast<double>(max_particles)))
      rd.fail_value(path + (cr ? ".count_rate" : ".mass_rate"), *t.get(cr ? "count_rate" : "mass_rate"),
                    "a rate and duration that insert at most " + std::to_string(max_particles) + " particles (this one may insert " +
                        number_text(most) + ")");
    // The box: where particles can be: in the gas domain, the period, on the inner side of every wall.
    const Vec3 corners[2] = {lo, hi};
    if (spec.gas != GasModel::none) {
      const fluid::GridSpec& g = spec.gas_spec.grid;
      if (lo.x < g.lo.x || lo.y < g.lo.y || lo.z < g.lo.z || hi.x > g.hi.x || hi.y > g.hi.y || hi.z > g.hi.z)
        rd.fail_value(upper_key, upper_node,
                      what + " inside the gas domain [" + number_text(g.lo.x) + ", " + number_text(g.hi.x) + "] x [" +
                          number_text(g.lo.y) + ", " + number_text(g.hi.y) + "] x [" + number_text(g.lo.z) + ", " +
                          number_text(g.hi.z) + "] m (SI)" + (cyl ? "" : " with " + path + ".lower"));
    }
    // (Centres are drawn below the upper corner, so it may be the period's end.)
    const double c_lo[3] = {lo.x, lo.y, lo.z}, c_hi[3] = {hi.x, hi.y, hi.z};
    for (int a = 0; a < 3; ++a)
      if (spec.periodic.on[a] && (c_lo[a] < spec.periodic.lo[a] || c_lo[a] >= spec.periodic.lo[a] + spec.periodic.len[a] ||
                                  c_hi[a] > spec.periodic.lo[a] + spec.periodic.len[a]))
        rd.fail_value(upper_key, upper_node, what + " inside the periodic box along every periodic axis" + (cyl ? "" : ", with " + path + ".lower"));
    for (const auto& w : spec.walls) {
      // A plane at rest: its signed distance is linear, so the box's corners bound it.
      if (w.shape != WallShape::plane || w.motion.moving()) continue;
      double best = -inf;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          for (int c = 0; c < 2; ++c) best = std::max(best, w.distance({corners[a].x, corners[b].y, corners[c].z}));
      if (!(best > in.size.smallest()))
        rd.fail_value(lower_key, lower_node,
                      (cyl ? "a cylinder whose bounding box reaches" : "a box reaching") + std::string(" inside wall '") +
                          w.name + "' by more than the smallest radius" + (cyl ? "" : " (with " + path + ".upper)") +
                          "; the whole " + (cyl ? "bounding box" : "box") + " lies outside it");
    }
    spec.insertions.push_back(std::move(in));
  }
}

void read_outlets(const Reader& rd, SceneSpec& spec) {
  const toml::array* os = rd.array_of_tables(rd.root(), "outlets");
  if (!os) return;
  for (std::size_t i = 0; i < os->size(); ++i) {
    const toml::table& t = *os->get(i)->as_table();
    const std::string path = "outlets[" + std::to_string(i) + "]";
    rd.check_keys(t, "outlets[]", path);
    OutletSpec o;
    const auto name = rd.string(t, "name", path);
    if (!name) rd.fail_missing(path + ".name", "a name (letters, digits, '_' and '-'), the outlet's columns in outlets.dat");
    if (name->empty() || name->size() > 64 ||
        !std::all_of(name->begin(), name->end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; }))
      rd.fail_value(path + ".name", *t.get("name"), "a name of 1 to 64 letters, digits, '_' and '-'");
    for (const auto& other : spec.outlets)
      if (other.name == *name) rd.fail_value(path + ".name", *t.get("name"), "a name no other outlet has");
    o.name = *name;
    if (!t.get("type")) rd.fail_missing(path + ".type", "\"plane\" or \"box\"");
    const auto type = *rd.string(t, "type", path);
    if (type != "plane" && type != "box") rd.fail_value(path + ".type", *t.get("type"), "\"plane\" or \"box\"");
    o.plane = type == "plane";
    if (o.plane) {
      rd.reject_unused(t, "lower", path, "a plane outlet has a point and a normal");
      rd.reject_unused(t, "upper", path, "a plane outlet has a point and a normal");
      o.point = rd.vec3_required(t, "point", path, Dim::length);
      const Vec3 n = rd.vec3_required(t, "normal", path, Dim::none);
      const double big = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
      if (!(big > 0.0)) rd.fail_value(path + ".normal", *t.get("normal"), "a non-zero vector (pointing out of the domain)");
      const Vec3 s{n.x / big, n.y / big, n.z / big};
      o.normal = s * (1.0 / std::sqrt(dot(s, s)));
    } else {
      rd.reject_unused(t, "point", path, "a box outlet has a lower and an upper corner");
      rd.reject_unused(t, "normal", path, "a box outlet has a lower and an upper corner");
      o.lower = rd.vec3_required(t, "lower", path, Dim::length);
      o.upper = rd.vec3_required(t, "upper", path, Dim::length);
      if (!(o.upper.x >= o.lower.x && o.upper.y >= o.lower.y && o.upper.z >= o.lower.z))
        rd.fail_value(path + ".upper", *t.get("upper"), "a corner at or above " + path + ".lower along every axis");
    }
    spec.outlets.push_back(o);
  }
}

}  // namespace cdm::scene
