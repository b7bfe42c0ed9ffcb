/// @file materials_contacts.cpp
/// @brief Materials and the contact parameters of each pair ([[materials]], [[contacts]]).
#include "sections.hpp"

#include <limits>
#include <string>

namespace cdm::scene {

void read_materials(const Reader& rd, SceneSpec& spec) {
  const toml::array* mats = rd.array_of_tables(rd.root(), "materials");
  if (!mats) rd.fail_missing("materials", "at least one [[materials]] entry");
  if (mats->size() > max_materials)
    throw SceneError(rd.file() + ": key 'materials' holds " + std::to_string(mats->size()) +
                     " [[materials]] entries: expected at most " + std::to_string(max_materials) +
                     " (a particle's material is held in one byte)");
  for (std::size_t i = 0; i < mats->size(); ++i) {
    const toml::table& t = *mats->get(i)->as_table();
    const std::string path = "materials[" + std::to_string(i) + "]";
    rd.check_keys(t, "materials[]", path);
    Material m;
    auto name = rd.string(t, "name", path);
    if (!name || name->empty()) rd.fail_missing(path + ".name", "a non-empty material name");
    for (const auto& other : spec.materials)
      if (other.name == *name) rd.fail_value(path + ".name", *t.get("name"), "a name not used by another material");
    m.name = *name;
    m.density = rd.positive(t, "density", path, Dim::density, false, 0.0);
    // Elastic constants: only Hertz–Mindlin pairs use them (checked in read_contacts).
    if (t.get("youngs_modulus") || t.get("poisson_ratio")) {
      if (!t.get("youngs_modulus"))
        rd.fail_missing(path + ".youngs_modulus", "a number > 0 [Pa] (poisson_ratio is given, so the pair is needed)");
      if (!t.get("poisson_ratio"))
        rd.fail_missing(path + ".poisson_ratio", "a number in (-1, 0.5) (youngs_modulus is given, so the pair is needed)");
      m.youngs_modulus = rd.positive(t, "youngs_modulus", path, Dim::pressure, true);
      m.poisson_ratio = rd.number_in(t, "poisson_ratio", path, Dim::none, true, 0.0, -1.0, true, 0.5, true, "in (-1, 0.5)");
    }
    m.fixed = rd.boolean(t, "fixed", path).value_or(false);
    if (m.fixed) {
      if (spec.tracers) rd.fail_value(path + ".fixed", *t.get("fixed"), "false for tracers (they move with the gas)");
    }
    spec.materials.push_back(m);
  }
  spec.pairs = PairTable(spec.materials.size());
}

void read_contacts(const Reader& rd, SceneSpec& spec) {
  const toml::array* cs = rd.array_of_tables(rd.root(), "contacts");
  if (!spec.normal_contact) {
    if (cs) throw SceneError(rd.file() + ": [[contacts]] is not used: modules.normal_contact is \"none\"");
    return;
  }
  if (!cs) return;  // missing pairs are reported where they are needed (check_initial_state)
  for (std::size_t i = 0; i < cs->size(); ++i) {
    const toml::table& t = *cs->get(i)->as_table();
    const std::string path = "contacts[" + std::to_string(i) + "]";
    rd.check_keys(t, "contacts[]", path);
    const toml::node* pn = t.get("pair");
    if (!pn) rd.fail_missing(path + ".pair", "an array of two material names");
    const toml::array* pa = pn->as_array();
    if (!pa || pa->size() != 2 || !pa->get(0)->is_string() || !pa->get(1)->is_string())
      rd.fail_value(path + ".pair", *pn, "an array of two material names");
    int idx[2];
    for (int k = 0; k < 2; ++k) {
      const std::string nm = pa->get(k)->as_string()->get();
      idx[k] = -1;
      for (std::size_t m = 0; m < spec.materials.size(); ++m)
        if (spec.materials[m].name == nm) idx[k] = static_cast<int>(m);
      if (idx[k] < 0) rd.fail_value(path + ".pair", *pn, "two names of materials in [[materials]]");
    }
    if (spec.pairs.get(idx[0], idx[1]).defined)
      rd.fail_value(path + ".pair", *pn, "a pair not already given by an earlier [[contacts]] entry");
    PairParams p;
    // The pair's force law: the scene's default (modules.normal_contact) unless it names one.
    p.law = rd.keyword(t, "model", path, contact_law_keywords, *spec.normal_contact);
    const bool hertz = p.law == ContactLaw::hertz_mindlin;
    p.en = rd.number_in(t, "en", path, Dim::none, true, 1.0, 0.0, true, 1.0, false, "in (0, 1]");
    if (!hertz) {
      p.kn = rd.positive(t, "kn", path, Dim::stiffness, true);
      rd.reject_unused(t, "damping", path, "the pair's model is linear_spring_dashpot, whose dashpot follows from en (eq 29)");
    } else {
      const std::string why = "the pair's model is hertz_mindlin, whose stiffnesses follow from the materials' "
                              "youngs_modulus and poisson_ratio";
      rd.reject_unused(t, "kn", path, why);
      rd.reject_unused(t, "kt_factor", path, why);
      rd.reject_unused(t, "etat_factor", path, why);
      for (int k = 0; k < 2; ++k)
        if (!(spec.materials[idx[k]].youngs_modulus > 0.0))
          rd.fail_missing("materials[" + std::to_string(idx[k]) + "].youngs_modulus",
                          "Young's modulus and Poisson ratio of material '" + spec.materials[idx[k]].name + "', because " +
                           path + " uses model hertz_mindlin");
      const Material& a = spec.materials[idx[0]];
      const Material& b = spec.materials[idx[1]];
      p.e_star = contact::effective_youngs_modulus(a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio);
      p.g_star = contact::effective_shear_modulus(a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio);
      p.hertz_damping = rd.keyword(t, "damping", path, hertz_damping_keywords, HertzDamping::exact_restitution);
    }
    if (spec.tangential == TangentialModel::none) {
      const std::string why = "modules.tangential is \"none\"";
      rd.reject_unused(t, "kt_factor", path, why);
      rd.reject_unused(t, "etat_factor", path, why);
      rd.reject_unused(t, "mu", path, why);
    } else {
      if (!hertz) {
        p.kt_factor = rd.positive(t, "kt_factor", path, Dim::none, false, 0.4);
        p.etat_factor = rd.number_in(t, "etat_factor", path, Dim::none, false, 0.5, 0.0, false,
                                     std::numeric_limits<double>::infinity(), false, ">= 0");
      }
      p.mu = rd.number_in(t, "mu", path, Dim::none, true, 0.0, 0.0, false, std::numeric_limits<double>::infinity(),
                          false, ">= 0");
    }
    if (spec.rolling == RollingModel::none)
      rd.reject_unused(t, "rolling_mu", path, "modules.rolling_resistance is \"none\"");
    else
      p.rolling_mu = rd.number_in(t, "rolling_mu", path, Dim::none, true, 0.0, 0.0, false,
                                  std::numeric_limits<double>::infinity(), false, ">= 0");
    spec.pairs.set(idx[0], idx[1], p);
  }
}

// A material's Young's modulus and Poisson ratio are used only by hertz_mindlin pairs.
void check_elastic_constants_used(const Reader& rd, const SceneSpec& spec) {
  const std::size_t nm = spec.materials.size();
  for (std::size_t a = 0; a < nm; ++a) {
    if (!(spec.materials[a].youngs_modulus > 0.0)) continue;
    bool used = false;
    for (std::size_t b = 0; b < nm && !used; ++b) {
      const PairParams& pp = spec.pairs.get(static_cast<int>(a), static_cast<int>(b));
      used = pp.defined && pp.law == ContactLaw::hertz_mindlin;
    }
    if (!used) {
      const std::string path = "materials[" + std::to_string(a) + "]";
      const toml::table& t = *rd.root().get("materials")->as_array()->get(a)->as_table();
      rd.reject_unused(t, "youngs_modulus", path,
                       "no [[contacts]] entry with model hertz_mindlin involves material '" + spec.materials[a].name + "'");
    }
  }
}

}  // namespace cdm::scene
