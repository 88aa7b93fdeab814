#pragma once
// Cutting-force coefficients of the mechanistic (linear edge-force) milling model
// (docs/forces.md): shear terms K_tc, K_rc, K_ac in N/mm² (force per unit chip area) and edge
// terms K_te, K_re, K_ae in N/mm (force per unit edge length), tangential, radial and axial.
//
// They come from a JSON file {"Ktc":…,"Krc":…,"Kac":…,"Kte":…,"Kre":…,"Kae":…} (extra keys
// allowed; "name" and "source" are kept) or from the bundled library of published sets
// (data/materials/*.json, compiled into the program), each naming its source.

#include <string>
#include <string_view>
#include <vector>

namespace cwe {

struct CuttingCoefficients {
  double ktc = 0.0, krc = 0.0, kac = 0.0;  // shear (cutting) terms, N/mm²
  double kte = 0.0, kre = 0.0, kae = 0.0;  // edge (ploughing) terms, N/mm
  std::string name;    // label for reports: the material and tool, or the file name
  std::string source;  // where the numbers come from (publication), if known
};

// Parses the JSON text of a coefficient set; `source` names it in errors and is the name when the
// text has no "name". Keys are case-sensitive. Throws cwe::InputError when the text is not valid
// JSON (with line and column), not an object, a key is missing, a value is not a finite number of
// magnitude at most kLargestInputValue (naming the key), or the three shear terms are all zero.
// Negative values are accepted: published sets differ in the sign convention of the axial terms.
CuttingCoefficients parse_cutting_coefficients(std::string_view json_text,
                                               const std::string& source);

// The bundled sets, by name (the file name without .json, e.g. "al7075-t6-carbide").
std::vector<std::string> bundled_materials();
// A bundled set by name (case-insensitive). An unknown name is an InputError listing the bundled
// names.
CuttingCoefficients bundled_coefficients(const std::string& name);

// `name_or_path`: a file when it ends in .json or contains '/'; otherwise a bundled material name
// (case-insensitive) if there is one, else an existing file. Throws cwe::InputError naming the
// file, or listing the bundled materials when it is neither.
CuttingCoefficients load_cutting_coefficients(const std::string& name_or_path);
// The source of load_cutting_coefficients' error for a name that is neither bundled nor a file
// (the caller knows which option gave it).
inline constexpr const char* kCoefficientNameSource = "cutting coefficients";

}  // namespace cwe
