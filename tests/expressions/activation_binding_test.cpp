// tests/expressions/activation_binding_test.cpp: --set NAME=VALUE binding
// (expressions/offline/activation_binding.h).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "expressions/offline/activation_binding.h"

namespace mimetic {
namespace {

const std::vector<std::string> kNames = {"frontalis_L", "frontalis_R", "procerus", "risorius_L"};

TEST(BindActivations, NamesValuesAndPairs) {
  std::vector<float> a;
  Diagnostics diag;
  ASSERT_TRUE(BindActivations(kNames, {"procerus=0.25", "frontalis=0.5"}, &a, &diag))
      << diag.Format();
  EXPECT_EQ(a, (std::vector<float>{0.5f, 0.5f, 0.25f, 0.f}));  // both sides from one name
  ASSERT_TRUE(BindActivations(kNames, {"frontalis_R=1", "frontalis_L=0"}, &a, &diag));
  EXPECT_EQ(a, (std::vector<float>{0.f, 1.f, 0.f, 0.f}));
}

TEST(BindActivations, Mistakes) {
  struct Case {
    std::vector<std::string> set;
    const char* message;
  };
  const std::vector<Case> cases = {
      {{"risorius=0.5"}, "unknown muscle 'risorius'; closest: risorius_L"},  // only one side
      {{"frontalis=0.5", "frontalis_L=0.2"}, "muscle 'frontalis_L' is set more than once"},
      {{"procerus=1.5"}, "value 1.5 is outside [0, 1]"},
      {{"procerus=nan"}, "value 'nan' is not a finite number"},
      {{"procerus"}, "expected NAME=VALUE"},
  };
  for (const Case& c : cases) {
    std::vector<float> a;
    Diagnostics diag;
    EXPECT_FALSE(BindActivations(kNames, c.set, &a, &diag)) << c.message;
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << diag.Format();
  }
}

}  // namespace
}  // namespace mimetic
