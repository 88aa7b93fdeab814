// JSON the user writes: every error located in the text.

#include "cwe/core/json_input.hpp"

#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"

namespace cwe {
namespace {

// Parsing `text` throws an InputError at line:column whose message contains `fragment`.
void expect_error(const std::string& text, int line, int column, const std::string& fragment) {
  SCOPED_TRACE(text);
  try {
    parse_json_input(text, "in.json");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, "in.json");
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
    EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
  }
}

TEST(JsonInput, ValuesAsNlohmannReadsThem) {
  const nlohmann::json j = parse_json_input(R"({"a": 1, "b": {"a": 2}, "c": [{"a": 3}]})", "x");
  EXPECT_EQ(j["a"], 1);
  EXPECT_EQ(j["b"]["a"], 2);  // the same key in other objects is no duplicate
  EXPECT_EQ(j["c"][0]["a"], 3);
}

TEST(JsonInput, ErrorsAreLocated) {
  expect_error("{\"a\": 1,\n \"a\": 2}", 2, 2, "key \"a\" written twice in one object");
  expect_error("{\"b\": {\"x\": 1, \"x\": 2}}", 1, 16, "key \"x\" written twice");
  // The second "x" as a key, though "x" is a value before it.
  expect_error("{\"v\": \"x\", \"o\": {\"x\": 1,\n\"x\" : 2}}", 2, 1, "key \"x\" written twice");
  expect_error("{\"a\": 1,\n \"b\": 1e400}", 2, 7, "number overflow parsing '1e400'");
  // nlohmann places a syntax error where it stops reading: after the bad token.
  expect_error("{\"a\": 1,\n \"b\": tru}", 2, 10, "not valid JSON: syntax error");
  expect_error("{\"a\": 1", 1, 8, "not valid JSON");
}

// JsonPlaces: every value's line and column, by JSON pointer, counted in bytes as the parse errors
// are.
TEST(JsonPlaces, LocatesValuesByPointer) {
  const std::string text =
      "{\"a\": 1,\n"
      "  \"b\": {\"c\": [10, \"x\", {\"d\": true}]},\n"
      "\t\"e/f\": null, \"g~\": \"s\"}";
  ASSERT_NO_THROW(parse_json_input(text, "in.json"));
  const JsonPlaces places(text, "in.json");
  const auto expect_at = [&](const std::string& pointer, int line, int column) {
    const SourceLocation at = places.at(pointer);
    EXPECT_EQ(at.source, "in.json") << pointer;
    EXPECT_EQ(at.line, line) << pointer;
    EXPECT_EQ(at.column, column) << pointer;
  };
  expect_at("", 1, 1);
  expect_at("/a", 1, 7);
  expect_at("/b", 2, 8);
  expect_at("/b/c", 2, 14);
  expect_at("/b/c/0", 2, 15);
  expect_at("/b/c/1", 2, 19);
  expect_at("/b/c/2/d", 2, 30);
  expect_at("/" + json_pointer_token("e/f"), 3, 9);
  expect_at("/" + json_pointer_token("g~"), 3, 21);
  // Not a value of the text: the source alone.
  EXPECT_EQ(places.at("/nope").line, 0);
}

// Values nested deeper than kDepth are skipped without recursion, whatever the depth.
TEST(JsonPlaces, DeepNestingIsSkipped) {
  const std::string text = "{\"k\": " + std::string(100000, '[') + std::string(100000, ']') +
                           ", \"after\": 2}";
  const JsonPlaces places(text, "deep.json");
  EXPECT_EQ(places.at("/k").column, 7);
  EXPECT_EQ(places.at("/after").column, static_cast<int>(text.find("2}")) + 1);
  EXPECT_EQ(places.at("/k/0/0/0/0/0").line, 0);
}

}  // namespace
}  // namespace cwe
