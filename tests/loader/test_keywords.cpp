// The keyword tables: every value has one keyword that parses back to it, and messages
// list the keywords in table order.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "cdm/solver/keywords.hpp"
#include "cdm/solver/scene.hpp"

namespace {

template <class E, std::size_t N>
void expect_round_trip(const cdm::Keywords<E, N>& table) {
  std::set<std::string> names;
  for (const auto& k : table) {
    EXPECT_TRUE(names.insert(k.name).second) << "keyword spelled twice: " << k.name;
    EXPECT_STREQ(cdm::keyword_of(table, k.value), k.name);
    ASSERT_TRUE(cdm::keyword_value(table, k.name).has_value()) << k.name;
    EXPECT_TRUE(*cdm::keyword_value(table, k.name) == k.value) << k.name;
  }
  EXPECT_FALSE(cdm::keyword_value(table, "no_such_keyword").has_value());
}

TEST(Keywords, EveryTableRoundTrips) {
  expect_round_trip(cdm::contact_law_keywords);
  expect_round_trip(cdm::hertz_damping_keywords);
  expect_round_trip(cdm::tangential_keywords);
  expect_round_trip(cdm::rolling_keywords);
  expect_round_trip(cdm::integrator_keywords);
  expect_round_trip(cdm::gas_model_keywords);
  expect_round_trip(cdm::coupling::drag_law_keywords);
  expect_round_trip(cdm::coupling::drag_update_keywords);
  expect_round_trip(cdm::coupling::kernel_keywords);
  expect_round_trip(cdm::coupling::slip_velocity_keywords);
  expect_round_trip(cdm::coupling::coupling_method_keywords);
  expect_round_trip(cdm::fluid::advection_keywords);
  expect_round_trip(cdm::fluid::pressure_backend_keywords);
  expect_round_trip(cdm::fluid::interpolation_keywords);
  expect_round_trip(cdm::fluid::field_type_keywords);
  expect_round_trip(cdm::fluid::boundary_keywords);
}

TEST(Keywords, ListsAsMessagesDo) {
  EXPECT_EQ(cdm::keyword_list(cdm::contact_law_keywords), "\"linear_spring_dashpot\" or \"hertz_mindlin\"");
  EXPECT_EQ(cdm::keyword_list(cdm::contact_law_keywords, [](cdm::ContactLaw) { return true; }, "none"),
            "\"none\", \"linear_spring_dashpot\" or \"hertz_mindlin\"");
  EXPECT_EQ(cdm::keyword_list(cdm::fluid::advection_keywords,
                              [](cdm::fluid::AdvectionScheme a) { return a != cdm::fluid::AdvectionScheme::none; }),
            "\"upwind\" or \"central\"");
  EXPECT_EQ(cdm::keyword_list(cdm::gas_model_keywords, [](cdm::GasModel g) { return g == cdm::GasModel::solved; }),
            "\"solved\"");
  EXPECT_STREQ(cdm::coupling::to_string(cdm::coupling::DragUpdate::explicit_force), "explicit");
  EXPECT_STREQ(cdm::to_string(cdm::IntegratorScheme::exponential_midpoint), "exponential_midpoint");
}

}  // namespace
