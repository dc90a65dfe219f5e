// Camera flights (megavox/render.h read_flight / parse_flight): the documented form, defaults, every kind of
// malformed input as a clear mv::Error naming the frame, and random byte damage never worse than an Error.
#include <random>

#include "megavox/error.h"
#include "megavox/render.h"
#include "test_support.h"

namespace mv::test {
namespace {

TEST(Flight, ReadsTheDocumentedForm) {
  const std::vector<Camera> f = parse_flight(
      R"({"fov": 35, "frames": [{"eye": [1, 2, 3], "target": [0, 0, 0], "up": [0, 0, 1]},
                                {"eye": [-1, 0.5, 2e1], "target": [0, 1, 0]}]})",
      "f.json");
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[0].fov, 35);
  EXPECT_EQ(f[0].eye[2], 3);
  EXPECT_EQ(f[0].up[2], 1);
  EXPECT_EQ(f[1].eye[2], 20);
  EXPECT_EQ(f[1].up[1], 1);  // default up
  EXPECT_EQ(parse_flight(R"({"frames": [{"eye": [1, 0, 0], "target": [0, 0, 0]}]})", "g").front().fov, 40);
}

TEST(Flight, MalformedFlightsAreClearErrors) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "not JSON"},
      {"[1, 2]", "JSON object"},
      {R"({"fov": 40})", "\"frames\""},
      {R"({"frames": []})", "\"frames\""},
      {R"({"frames": 3})", "\"frames\""},
      {R"({"fov": 0, "frames": [{"eye": [1, 0, 0], "target": [0, 0, 0]}]})", "\"fov\""},
      {R"({"fov": "wide", "frames": [{"eye": [1, 0, 0], "target": [0, 0, 0]}]})", "\"fov\""},
      {R"({"frames": [{"target": [0, 0, 0]}]})", "frame 0: no \"eye\""},
      {R"({"frames": [{"eye": [1, 0, 0], "target": [0, 0, 0]}, 7]})", "frame 1: not an object"},
      {R"({"frames": [{"eye": [1, 0], "target": [0, 0, 0]}]})", "three numbers"},
      {R"({"frames": [{"eye": [1, 0, "x"], "target": [0, 0, 0]}]})", "three finite numbers"},
      {R"({"frames": [{"eye": [1e999, 0, 0], "target": [0, 0, 0]}]})", "not JSON"},
      {R"({"frames": [{"eye": [0, 0, 0], "target": [0, 0, 0]}]})", "the same point"},
  };
  for (const auto& c : cases) {
    const auto& text = c.first;  // not a structured binding: clang 14 (the sanitizer build) cannot capture one
    const auto& want = c.second;
    SCOPED_TRACE(text);
    const std::string msg = error_message([&] { parse_flight(text, "f.json"); });
    EXPECT_NE(msg.find("f.json"), std::string::npos) << msg;
    EXPECT_NE(msg.find(want), std::string::npos) << msg;
  }
  EXPECT_NE(error_message([] { read_flight("/nonexistent/flight.json"); }).find("flight.json"), std::string::npos);
}

// Random damage to a good flight: parsed, or refused with mv::Error, never anything else.
TEST(Flight, DamagedFlightsNeverCrash) {
  const std::string good = R"({"fov": 35, "frames": [{"eye": [1, 2, 3], "target": [0, 0, 0], "up": [0, 0, 1]}]})";
  std::mt19937 rng(4);
  for (int i = 0; i < 3000; ++i) {
    std::string s = good;
    for (int k = 0, n = 1 + rng() % 4; k < n; ++k) {
      const size_t at = rng() % s.size();
      switch (rng() % 3) {
        case 0: s[at] = static_cast<char>(rng()); break;
        case 1: s.erase(at, 1 + rng() % 4); break;
        default: s.insert(at, 1, "[]{},:\"0e-"[rng() % 10]); break;
      }
      if (s.empty()) s = "{";
    }
    try {
      parse_flight(s, "damaged");
    } catch (const Error&) {
    }
  }
}

}  // namespace
}  // namespace mv::test
