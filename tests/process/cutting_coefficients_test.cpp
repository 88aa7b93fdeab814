#include "cwe/process/cutting_coefficients.hpp"
#include "input_error.hpp"
#include "source_dir.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"

namespace cwe {
namespace {

constexpr const char* kGoodSet = R"({
  "name": "test set",
  "source": "a textbook",
  "comment": "extra keys are ignored",
  "tool": {"flutes": 4},
  "Ktc": 800, "Krc": 170.5, "Kac": -220,
  "Kte": 27.5, "Kre": 30, "Kae": 1.5
})";

std::filesystem::path materials_dir() { return test::source_dir() / "data" / "materials"; }

// The numbers are copied from the JSON text, so they compare exactly.
void expect_same_set(const CuttingCoefficients& a, const CuttingCoefficients& b) {
  EXPECT_EQ(a.ktc, b.ktc);
  EXPECT_EQ(a.krc, b.krc);
  EXPECT_EQ(a.kac, b.kac);
  EXPECT_EQ(a.kte, b.kte);
  EXPECT_EQ(a.kre, b.kre);
  EXPECT_EQ(a.kae, b.kae);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.source, b.source);
}

TEST(CuttingCoefficients, ParsesASetWithExtraKeys) {
  const CuttingCoefficients set = parse_cutting_coefficients(kGoodSet, "good.json");
  EXPECT_EQ(set.ktc, 800.0);
  EXPECT_EQ(set.krc, 170.5);
  EXPECT_EQ(set.kac, -220.0);  // negative terms are published and accepted
  EXPECT_EQ(set.kte, 27.5);
  EXPECT_EQ(set.kre, 30.0);
  EXPECT_EQ(set.kae, 1.5);
  EXPECT_EQ(set.name, "test set");
  EXPECT_EQ(set.source, "a textbook");
}

TEST(CuttingCoefficients, NameDefaultsToTheSource) {
  const CuttingCoefficients set = parse_cutting_coefficients(
      R"({"Ktc": 1, "Krc": 0, "Kac": 0, "Kte": 0, "Kre": 0, "Kae": 0})", "plain.json");
  EXPECT_EQ(set.name, "plain.json");
  EXPECT_EQ(set.source, "");
}

TEST(CuttingCoefficients, MissingKeyIsNamed) {
  const std::string text = R"({"Ktc": 800, "Krc": 170, "Kac": 220, "Kte": 27, "Kae": 1})";
  EXPECT_INPUT_ERROR(parse_cutting_coefficients(text, "set.json"),
                     "set.json: error: missing \"Kre\"");
  EXPECT_INPUT_ERROR(parse_cutting_coefficients(text, "set.json"),
                     "Ktc, Krc, Kac (shear terms, N/mm²) and Kte, Kre, Kae (edge terms, N/mm)");
  // Keys are case-sensitive; the message points at the near miss.
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"ktc": 800, "Krc": 170, "Kac": 220, "Kte": 27, "Kre": 30, "Kae": 1})", "set.json"),
      "missing \"Ktc\" (found \"ktc\"; keys are case-sensitive)");
}

TEST(CuttingCoefficients, ValuesMustBeFiniteNumbers) {
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": "800", "Krc": 170, "Kac": 220, "Kte": 27, "Kre": 30, "Kae": 1})", "s.json"),
      "s.json: error: \"Ktc\": expected a number in N/mm², found \"800\"");
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": 800, "Krc": 170, "Kac": 220, "Kte": null, "Kre": 30, "Kae": 1})", "s.json"),
      "\"Kte\": expected a number in N/mm, found null");
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": 800, "Krc": 170, "Kac": 220, "Kte": 27, "Kre": "NaN", "Kae": 1})", "s.json"),
      "\"Kre\": expected a number in N/mm, found \"NaN\"");
  // NaN is no JSON literal: a syntax error.
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": NaN, "Krc": 170, "Kac": 220, "Kte": 27, "Kre": 30, "Kae": 1})", "s.json"),
      "s.json:1:9: error: not valid JSON: syntax error while parsing value - invalid literal");
  // A number that overflows a double.
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": 1e999, "Krc": 170, "Kac": 220, "Kte": 27, "Kre": 30, "Kae": 1})", "s.json"),
      "s.json:1:9: error: not valid JSON: number overflow parsing '1e999'");
  // Finite but beyond any machining quantity (kLargestInputValue).
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": 800, "Krc": 170, "Kac": -2e9, "Kte": 27, "Kre": 30, "Kae": 1})", "s.json"),
      "\"Kac\": -2000000000.0 N/mm² is out of range");
}

TEST(CuttingCoefficients, NameAndSourceMustBeStrings) {
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"name": 7, "Ktc": 800, "Krc": 170, "Kac": 220, "Kte": 27, "Kre": 30, "Kae": 1})",
          "s.json"),
      "\"name\": expected a string, found 7");
}

TEST(CuttingCoefficients, AllZeroShearTermsAreRefused) {
  EXPECT_INPUT_ERROR(
      parse_cutting_coefficients(
          R"({"Ktc": 0, "Krc": 0.0, "Kac": -0.0, "Kte": 27, "Kre": 30, "Kae": 1})", "z.json"),
      "z.json: error: the shear terms Ktc, Krc and Kac are all zero");
}

TEST(CuttingCoefficients, SyntaxErrorGivesLineAndColumn) {
  // The missing ':' after "Krc" is found at the '2' on line 3, column 9.
  EXPECT_INPUT_ERROR(parse_cutting_coefficients("{\n  \"Ktc\": 1,\n  \"Krc\" 2\n}", "bad.json"),
                     "bad.json:3:9: error: not valid JSON");
  EXPECT_INPUT_ERROR(parse_cutting_coefficients("", "empty.json"), "empty.json:1:1: error:");
}

TEST(CuttingCoefficients, NotAnObject) {
  EXPECT_INPUT_ERROR(parse_cutting_coefficients("[800, 170, 220, 27, 30, 1]", "list.json"),
                     "list.json: error: expected a JSON object");
  EXPECT_INPUT_ERROR(parse_cutting_coefficients("796", "number.json"),
                     "number.json: error: expected a JSON object");
}

TEST(BundledMaterials, EveryFileIsBundledAndMatchesItsFile) {
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(materials_dir())) {
    if (entry.path().extension() == ".json") files.push_back(entry.path().stem().string());
  }
  std::sort(files.begin(), files.end());
  const std::vector<std::string> names = bundled_materials();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names, files);  // sorted, one per file: the embedded copy is not stale

  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const CuttingCoefficients bundled = bundled_coefficients(name);
    EXPECT_FALSE(bundled.name.empty());
    EXPECT_FALSE(bundled.source.empty());
    EXPECT_NE(bundled.source.find("20"), std::string::npos) << "a citation has a year";
    // The embedded text gives the same set as the file in the source tree.
    const std::filesystem::path file = materials_dir() / (name + ".json");
    expect_same_set(bundled, load_cutting_coefficients(file.string()));
  }
}

TEST(BundledMaterials, PublishedNumbers) {
  // As printed in Duan et al. 2021 (Chin. J. Mech. Eng., doi:10.1186/s10033-021-00536-9),
  // Table 5; see the files for the rows.
  const CuttingCoefficients carbide = bundled_coefficients("al7075-t6-carbide");
  EXPECT_EQ(carbide.ktc, 767.01);
  EXPECT_EQ(carbide.krc, 168.8);
  EXPECT_EQ(carbide.kac, 222.0);
  EXPECT_EQ(carbide.kte, 27.7);
  EXPECT_EQ(carbide.kre, 26.6);
  EXPECT_EQ(carbide.kae, 0.7);
  const CuttingCoefficients hss = bundled_coefficients("al7075-hss");
  EXPECT_EQ(hss.ktc, 951.365);
  EXPECT_EQ(hss.krc, 262.597);
  EXPECT_EQ(hss.kac, 323.33);
  EXPECT_EQ(hss.kte, 11.115);
  EXPECT_EQ(hss.kre, 11.314);
  EXPECT_EQ(hss.kae, 1.105);
}

TEST(BundledMaterials, LookupIsCaseInsensitive) {
  expect_same_set(bundled_coefficients("AL7075-T6-Carbide"),
                  bundled_coefficients("al7075-t6-carbide"));
  expect_same_set(load_cutting_coefficients("Al7075-HSS"), bundled_coefficients("al7075-hss"));
}

TEST(BundledMaterials, UnknownNameListsTheBundledNames) {
  EXPECT_INPUT_ERROR(bundled_coefficients("unobtainium"),
                     "unknown material 'unobtainium' (bundled: al7075-hss, al7075-t6-carbide)");
  EXPECT_INPUT_ERROR(load_cutting_coefficients("unobtainium"),
                     "'unobtainium' is neither a bundled material (al7075-hss, al7075-t6-carbide) "
                     "nor a file");
}

TEST(CuttingCoefficientFile, LoadsFromAPath) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "cwe-cutting-coefficients-test";
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "mine.json";
  {
    std::ofstream out(file);
    out << kGoodSet;
  }
  const CuttingCoefficients set = load_cutting_coefficients(file.string());
  expect_same_set(set, parse_cutting_coefficients(kGoodSet, "good.json"));

  // A file without .json is read when it exists and is no bundled name.
  const std::filesystem::path plain = dir / "mine.coefficients";
  {
    std::ofstream out(plain);
    out << R"({"Ktc": 1, "Krc": 2, "Kac": 3, "Kte": 4, "Kre": 5, "Kae": 6})";
  }
  EXPECT_EQ(load_cutting_coefficients(plain.string()).kae, 6.0);
  EXPECT_EQ(load_cutting_coefficients(plain.string()).name, plain.string());

  // Errors inside a file name the file.
  const std::filesystem::path broken = dir / "broken.json";
  {
    std::ofstream out(broken);
    out << R"({"Ktc": 800})";
  }
  EXPECT_INPUT_ERROR(load_cutting_coefficients(broken.string()),
                     broken.string() + ": error: missing \"Krc\"");
  EXPECT_INPUT_ERROR(load_cutting_coefficients((dir / "absent.json").string()),
                     "absent.json: error: cannot open the cutting-coefficient file");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cwe
