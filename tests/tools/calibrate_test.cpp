// tests/tools/calibrate_test.cpp: `mimetic calibrate`'s usage errors, the numeric options
// included; each is refused with exit 2 and a message naming the option, the value and what
// was expected, before any input is read.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.h"

namespace mimetic {
namespace {

void ExpectUsage(const std::vector<std::string>& args, const std::string& message) {
  const test::ToolResult r = test::RunTool(args);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
}

TEST(CalibrateCli, UsageAndBadNumbers) {
  const test::ToolResult help = test::RunTool({"calibrate", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--normal-weight K"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--crease-fraction F"), std::string::npos) << help.output;
  ExpectUsage({"calibrate"}, "--out FILE is required");
  ExpectUsage({"calibrate", "--out", "t.json", "extra"}, "takes no positional arguments");
  ExpectUsage({"calibrate", "--out", "t.json", "--passes", "0"},
              "--passes '0': expected a whole number in [1, 20]");
  for (const char* bad : {"x", "-1", "101", "nan", "inf", ""})
    ExpectUsage({"calibrate", "--out", "t.json", "--normal-weight", bad},
                std::string("--normal-weight '") + bad + "': expected a number in [0, 100]");
  for (const char* bad : {"x", "-0.1", "1.5", "nan", "inf", ""})
    ExpectUsage({"calibrate", "--out", "t.json", "--crease-fraction", bad},
                std::string("--crease-fraction '") + bad + "': expected a number in [0, 1]");
}

}  // namespace
}  // namespace mimetic
