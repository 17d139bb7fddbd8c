// tests/io/expression_file_test.cpp: expression files (io/expression_file.h): a round trip,
// the example file, and the bad-input table.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/expression_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

TEST(ExpressionFile, ReadsTheExampleAndRoundTrips) {
  Expression e;
  Diagnostics diag;
  ASSERT_TRUE(LoadExpression(test::SourceDir() + "/tests/data/expressions/smile_L.expression.json",
                             &e, &diag))
      << diag.Format();
  EXPECT_EQ(e.name, "mouthSmile_L");
  // Members come back sorted by name (the parser's objects are ordered maps).
  ASSERT_EQ(e.activations.size(), 3u);
  EXPECT_EQ(e.activations[0], (std::pair<std::string, float>{"frontalis_inner_L", 0.f}));
  EXPECT_EQ(e.activations[1], (std::pair<std::string, float>{"risorius_L", 0.42f}));
  EXPECT_EQ(e.activations[2], (std::pair<std::string, float>{"zygomaticus_major_L", 1.f}));
  ASSERT_EQ(e.solve_numbers.size(), 2u);
  EXPECT_EQ(e.solve_numbers[0], (std::pair<std::string, double>{"ratio", 0.6668}));
  EXPECT_EQ(e.solve_numbers[1], (std::pair<std::string, double>{"residual", 317.383}));
  ASSERT_EQ(e.solve_strings.size(), 2u);
  const std::string path = test::TempDir() + "/e.expression.json";
  ASSERT_TRUE(SaveExpression(path, e, &diag)) << diag.Format();
  Expression back;
  ASSERT_TRUE(LoadExpression(path, &back, &diag)) << diag.Format();
  EXPECT_EQ(back.name, e.name);
  EXPECT_EQ(back.activations, e.activations);  // six decimals hold these exactly as floats
  EXPECT_EQ(back.solve_numbers, e.solve_numbers);
  EXPECT_EQ(back.solve_strings, e.solve_strings);
}

TEST(ExpressionFile, BadInputsSayWhatAndWhere) {
  const std::string good =
      R"({"format": "mimetic-expression", "version": 1, "name": "x", "activations": {"a": 0.5}})";
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  auto append = [&](const std::string& member) {  // one more top-level member
    return good.substr(0, good.size() - 1) + ", " + member + "}";
  };
  struct Case {
    std::string text;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"", "not valid JSON"},
      {"[1, 2]", "expected an object with \"format\": \"mimetic-expression\""},
      {with("\"mimetic-expression\"", "\"mimetic-rig\""), "format"},
      {with("\"version\": 1", "\"version\": 2"), "version"},
      {with("\"name\": \"x\", ", ""), "name"},
      {with("\"name\": \"x\"", "\"name\": \"\""), "name"},
      {with("{\"a\": 0.5}", "[0.5]"), "activations"},
      {with("{\"a\": 0.5}", "{\"a\": 1.5}"), "activations.a: is 1.5; expected an activation in [0, 1]"},
      {with("{\"a\": 0.5}", "{\"a\": \"half\"}"), "activations.a: is \"half\"; expected an activation"},
      {with("{\"a\": 0.5}", "{\"\": 0.5}"), "activations: has an empty muscle name"},
      {append("\"solve\": {\"steps\": [1]}"), "solve.steps: is array of 1 elements; expected a number or a string"},
      {append("\"colour\": 3"), "colour"},
      {std::string(100, '[') + std::string(100, ']'), "nest"},
  };
  for (const Case& c : cases) {
    Expression e;
    Diagnostics diag;
    EXPECT_FALSE(ParseExpression(c.text, "f.json", &e, &diag)) << c.text;
    EXPECT_NE(diag.Format().find(c.message), std::string::npos)
        << c.text << "\n" << diag.Format();
  }
}

}  // namespace
}  // namespace mimetic
