#include "gcode_expression.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

#include "cwe/core/text_file.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/geometry/vec.hpp"
#include "gcode_tolerance.hpp"

namespace cwe::gcode {
namespace {

// LinuxCNC's TOLERANCE_EQUAL: EQ and NE compare within it.
constexpr double kEqualTolerance = tol::kGcodeEqual;

enum class Op {
  kRightBracket,
  kPower,
  kTimes,
  kDivide,
  kModulo,
  kPlus,
  kMinus,
  kLt,
  kEq,
  kNe,
  kLe,
  kGe,
  kGt,
  kAnd,
  kXor,
  kOr
};

// LinuxCNC's precedence(): right bracket 1, logical 2, relational 3, plus-like 4, times-like 5,
// power 6.
int precedence(Op op) {
  switch (op) {
    case Op::kRightBracket:
      return 1;
    case Op::kAnd:
    case Op::kXor:
    case Op::kOr:
      return 2;
    case Op::kLt:
    case Op::kEq:
    case Op::kNe:
    case Op::kLe:
    case Op::kGe:
    case Op::kGt:
      return 3;
    case Op::kPlus:
    case Op::kMinus:
      return 4;
    case Op::kTimes:
    case Op::kDivide:
    case Op::kModulo:
      return 5;
    case Op::kPower:
      break;
  }
  return 6;
}

enum class Unary {
  kAbs,
  kAcos,
  kAsin,
  kAtan,
  kCos,
  kExists,
  kExp,
  kFix,
  kFup,
  kLn,
  kRound,
  kSin,
  kSqrt,
  kTan
};

double degrees(double radians) { return radians * 180.0 / kPi; }
double radians(double degrees) { return degrees * kPi / 180.0; }

}  // namespace

Parameters::Parameters() : numbered_(kNumbered, 0.0), locals_(1) {
  // LinuxCNC's defaults without a parameter file: G54 in use.
  numbered_[5220] = 1.0;
}

std::optional<double> Parameters::named(std::string_view name) const {
  if (!name.empty() && name.front() == '_') {
    if (predefined_) {
      if (const std::optional<double> value = predefined_(name)) return value;
    }
    const auto it = globals_.find(name);
    if (it != globals_.end()) return it->second;
    return std::nullopt;
  }
  const Names& scope = locals_.back();
  const auto it = scope.find(name);
  if (it != scope.end()) return it->second;
  return std::nullopt;
}

bool Parameters::read_only_name(std::string_view name) const {
  return !name.empty() && name.front() == '_' && predefined_ && predefined_(name).has_value();
}

void Parameters::set_named(const std::string& name, double value) {
  if (!name.empty() && name.front() == '_') {
    globals_[name] = value;
  } else {
    locals_.back()[name] = value;
  }
}

void ValueReader::fail(std::size_t i, const std::string& message) const {
  throw InputError(SourceLocation{where_.source, where_.line, line_.column(i)}, message);
}

double ValueReader::real(std::size_t& i) const {
  const std::size_t start = i;
  const char c = line_.at(i);
  const char c1 = line_.at(i + 1);
  if (c == '\0') fail(i, "no characters found in reading a real value");
  double value = 0.0;
  const auto signed_value = [&](char next) {
    return next != '\0' && !(next >= '0' && next <= '9') && next != '.';
  };
  if (c == '[') {
    value = expression(i);
  } else if (c == '#') {
    value = parameter(i, false);
  } else if (c == '+' && signed_value(c1)) {
    ++i;
    value = real(i);
  } else if (c == '-' && signed_value(c1)) {
    ++i;
    value = -real(i);
  } else if (c >= 'a' && c <= 'z') {
    value = unary(i);
  } else {
    value = number(i);
  }
  if (std::isnan(value)) fail(start, "calculation resulted in 'not a number'");
  if (std::isinf(value)) fail(start, "calculation resulted in 'infinity'");
  return value;
}

int ValueReader::integer(std::size_t& i) const {
  const std::size_t start = i;
  const double value = real(i);
  // LinuxCNC's read_integer_value: floor, or ceil when within 0.0001 below an integer.
  if (!(std::abs(value) < 2147483647.0)) {
    fail(start, fmt::format("integer value out of range: {:g}", value));
  }
  const double lower = std::floor(value);
  if (value - lower > 1.0 - tol::kGcodeIntegerWord) return static_cast<int>(std::ceil(value));
  if (value - lower > tol::kGcodeIntegerWord) {
    fail(start, fmt::format("non-integer value for integer: {:g}", value));
  }
  return static_cast<int>(lower);
}

PlainNumber scan_number(const std::string& s, std::size_t i) {
  PlainNumber n;
  std::size_t j = i;
  bool negative = false;
  if (j < s.size() && (s[j] == '+' || s[j] == '-')) negative = s[j++] == '-';
  const std::size_t digits_begin = j;
  int digits = 0, points = 0;
  for (; j < s.size() && ((s[j] >= '0' && s[j] <= '9') || s[j] == '.'); ++j) {
    if (s[j] == '.') {
      ++points;
    } else {
      ++digits;
    }
  }
  n.end = j;
  if (digits == 0) {
    n.status = PlainNumber::Status::kNoDigits;
    return n;
  }
  if (points > 1) {
    n.status = PlainNumber::Status::kTwoPoints;
    return n;
  }
  const auto [end, error] =
      std::from_chars(s.data() + digits_begin, s.data() + j, n.value, std::chars_format::fixed);
  if (error == std::errc::result_out_of_range || !std::isfinite(n.value) ||
      n.value > kLargestInputValue) {
    n.status = PlainNumber::Status::kOutOfRange;
  } else if (error != std::errc() || end != s.data() + j) {
    n.status = PlainNumber::Status::kBad;
  }
  if (negative) n.value = -n.value;
  return n;
}

double ValueReader::number(std::size_t& i) const {
  const PlainNumber n = scan_number(line_.code, i);
  switch (n.status) {
    case PlainNumber::Status::kOk:
      i = n.end;
      return n.value;
    case PlainNumber::Status::kOutOfRange:
      fail(i, fmt::format("number out of range (larger than {:g})", kLargestInputValue));
    default:
      fail(i, fmt::format("bad number format: '{}'",
                          line_.code.substr(i, std::max<std::size_t>(1, n.end - i))));
  }
}

std::string ValueReader::name(std::size_t& i) const {
  // At '<': the name runs to the next '>' (blanks were removed and letters lowered).
  const std::size_t open = i++;
  const std::size_t close = line_.code.find('>', i);
  if (close == std::string::npos) fail(open, "named parameter not terminated: '>' missing");
  std::string text = line_.code.substr(i, close - i);
  if (text.empty()) fail(open, "empty parameter name: #<>");
  i = close + 1;
  return text;
}

double ValueReader::parameter(std::size_t& i, bool check_exists) const {
  const std::size_t hash = i++;  // at '#'
  if (line_.at(i) == '<') {
    const std::string text = name(i);
    const std::optional<double> value = parameters_.named(text);
    if (check_exists) return value ? 1.0 : 0.0;
    if (!value) fail(hash, fmt::format("named parameter #<{}> not defined", text));
    return *value;
  }
  const int index = integer(i);
  if (check_exists) return index >= 1 && index < Parameters::kNumbered ? 1.0 : 0.0;
  if (index < 1 || index >= Parameters::kNumbered) {
    fail(hash, fmt::format("parameter number out of range: #{} (parameters are #1 to #{})", index,
                           Parameters::kNumbered - 1));
  }
  if (index >= 5420 && index <= 5428 && !parameters_.position_readable()) {
    fail(hash, "cannot read current position with cutter radius compensation on");
  }
  return parameters_.numbered(index);
}

double ValueReader::expression(std::size_t& i) const {
  // LinuxCNC's read_real_expression: a stack machine evaluating operations of equal precedence
  // left to right.
  const std::size_t open = i++;  // at '['
  constexpr std::size_t kStack = 7;
  std::array<double, kStack> values{};
  std::array<Op, kStack> ops{};
  std::array<std::size_t, kStack> at{};  // where each operator was read, for messages
  const auto read_op = [&](std::size_t slot) {
    at[slot] = i;
    const char c = line_.at(i++);
    const auto word = [&](std::string_view rest, Op op, const char* name) {
      if (line_.code.compare(i, rest.size(), rest) != 0) {
        fail(i - 1, fmt::format("unknown operation name starting with {}", name));
      }
      i += rest.size();
      return op;
    };
    switch (c) {
      case '+':
        return Op::kPlus;
      case '-':
        return Op::kMinus;
      case '/':
        return Op::kDivide;
      case '*':
        if (line_.at(i) == '*') {
          ++i;
          return Op::kPower;
        }
        return Op::kTimes;
      case ']':
        return Op::kRightBracket;
      case 'a':
        return word("nd", Op::kAnd, "A");
      case 'm':
        return word("od", Op::kModulo, "M");
      case 'o':
        return word("r", Op::kOr, "O");
      case 'x':
        return word("or", Op::kXor, "X");
      case 'e':
        return word("q", Op::kEq, "E");
      case 'n':
        return word("e", Op::kNe, "N");
      case 'g':
        if (line_.at(i) == 't') return word("t", Op::kGt, "G");
        return word("e", Op::kGe, "G");
      case 'l':
        if (line_.at(i) == 't') return word("t", Op::kLt, "L");
        return word("e", Op::kLe, "L");
      case '\0':
        fail(open, "unclosed expression: ']' missing");
      default:
        fail(i - 1, fmt::format("unknown operation: '{}'",
                                c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c));
    }
  };
  const auto apply = [&](std::size_t left, Op op, std::size_t where) {
    double& a = values[left];
    const double b = values[left + 1];
    switch (op) {
      case Op::kDivide:
        if (b == 0.0) fail(where, "attempt to divide by zero");
        a /= b;
        break;
      case Op::kModulo:  // always a positive answer, as LinuxCNC
        a = std::fmod(a, b);
        if (a < 0.0) a += std::abs(b);
        break;
      case Op::kPower:
        if (a < 0.0 && std::floor(b) != b) {
          fail(where, "attempt to raise a negative number to a non-integer power");
        }
        a = std::pow(a, b);
        break;
      case Op::kTimes:
        a *= b;
        break;
      case Op::kPlus:
        a += b;
        break;
      case Op::kMinus:
        a -= b;
        break;
      case Op::kAnd:
        a = (a == 0.0 || b == 0.0) ? 0.0 : 1.0;
        break;
      case Op::kXor:
        a = ((a == 0.0) != (b == 0.0)) ? 1.0 : 0.0;
        break;
      case Op::kOr:
        a = (a != 0.0 || b != 0.0) ? 1.0 : 0.0;
        break;
      case Op::kLt:
        a = a < b ? 1.0 : 0.0;
        break;
      case Op::kGt:
        a = a > b ? 1.0 : 0.0;
        break;
      case Op::kEq:
        a = std::abs(a - b) < kEqualTolerance ? 1.0 : 0.0;
        break;
      case Op::kNe:
        a = std::abs(a - b) >= kEqualTolerance ? 1.0 : 0.0;
        break;
      case Op::kLe:  // exact in 2.9 (later versions compare within the tolerance)
        a = a <= b ? 1.0 : 0.0;
        break;
      case Op::kGe:
        a = a >= b ? 1.0 : 0.0;
        break;
      case Op::kRightBracket:
        break;
    }
  };
  values[0] = real(i);
  ops[0] = read_op(0);
  std::size_t top = 1;
  while (ops[0] != Op::kRightBracket) {
    values[top] = real(i);
    ops[top] = read_op(top);
    if (precedence(ops[top]) > precedence(ops[top - 1])) {
      ++top;  // at most six levels: the stack never overflows
      continue;
    }
    while (precedence(ops[top]) <= precedence(ops[top - 1])) {
      apply(top - 1, ops[top - 1], at[top - 1]);
      ops[top - 1] = ops[top];
      at[top - 1] = at[top];
      if (top > 1 && precedence(ops[top - 1]) <= precedence(ops[top - 2])) {
        --top;
      } else {
        break;
      }
    }
  }
  return values[0];
}

double ValueReader::unary(std::size_t& i) const {
  const std::size_t start = i;
  static constexpr std::pair<std::string_view, Unary> kNames[] = {
      {"abs", Unary::kAbs},   {"acos", Unary::kAcos},   {"asin", Unary::kAsin},
      {"atan", Unary::kAtan}, {"cos", Unary::kCos},     {"exists", Unary::kExists},
      {"exp", Unary::kExp},   {"fix", Unary::kFix},     {"fup", Unary::kFup},
      {"ln", Unary::kLn},     {"round", Unary::kRound}, {"sin", Unary::kSin},
      {"sqrt", Unary::kSqrt}, {"tan", Unary::kTan}};
  // The longest name that matches (exists before exp, acos before …).
  std::optional<Unary> op;
  std::size_t length = 0;
  for (const auto& [text, kind] : kNames) {
    if (text.size() > length && line_.code.compare(i, text.size(), text) == 0) {
      op = kind;
      length = text.size();
    }
  }
  if (!op) {
    fail(start, fmt::format("unknown word starting with '{}' where a unary operation could be "
                            "(ABS, ACOS, ASIN, ATAN, COS, EXISTS, EXP, FIX, FUP, LN, ROUND, SIN, "
                            "SQRT, TAN)",
                            static_cast<char>(line_.code[i] - 'a' + 'A')));
  }
  i += length;
  if (line_.at(i) != '[') fail(i, "left bracket missing after unary operation name");
  if (*op == Unary::kExists) {
    ++i;
    if (line_.at(i) != '#') fail(i, "expected # reading parameter");
    const double exists = parameter(i, true);
    if (line_.at(i) != ']') fail(i, "expected ] reading bracketed parameter");
    ++i;
    return exists;
  }
  double value = expression(i);
  switch (*op) {
    case Unary::kAbs:
      return std::abs(value);
    case Unary::kAcos:
    case Unary::kAsin:
      if (value < -1.0 || value > 1.0) {
        fail(start, fmt::format("argument to {} out of range: {:g}",
                                *op == Unary::kAcos ? "ACOS" : "ASIN", value));
      }
      return degrees(*op == Unary::kAcos ? std::acos(value) : std::asin(value));
    case Unary::kAtan: {
      if (line_.at(i) != '/') fail(i, "slash missing after first ATAN argument");
      ++i;
      if (line_.at(i) != '[') fail(i, "left bracket missing after slash with ATAN");
      const double x = expression(i);
      return degrees(std::atan2(value, x));
    }
    case Unary::kCos:
      return std::cos(radians(value));
    case Unary::kExp:
      return std::exp(value);
    case Unary::kFix:
      return std::floor(value);
    case Unary::kFup:
      return std::ceil(value);
    case Unary::kLn:
      if (value <= 0.0) fail(start, "zero or negative argument to LN");
      return std::log(value);
    case Unary::kRound:  // LinuxCNC: (int)(x ± 0.5)
      return std::trunc(value + (value < 0.0 ? -0.5 : 0.5));
    case Unary::kSin:
      return std::sin(radians(value));
    case Unary::kSqrt:
      if (value < 0.0) fail(start, "negative argument to SQRT");
      return std::sqrt(value);
    case Unary::kTan:
      return std::tan(radians(value));
    case Unary::kExists:
      break;
  }
  return value;
}

ParameterSetting ValueReader::setting(std::size_t& i) const {
  const std::size_t hash = i++;  // at '#'
  ParameterSetting s;
  if (line_.at(i) == '<') {
    s.name = name(i);
    if (parameters_.read_only_name(s.name)) {
      fail(hash, fmt::format("#<{}> is a read-only parameter", s.name));
    }
  } else {
    s.index = integer(i);
    if (s.index < 1 || s.index >= Parameters::kNumbered) {
      fail(hash, fmt::format("parameter number out of range: #{} (parameters are #1 to #{})",
                             s.index, Parameters::kNumbered - 1));
    }
    if (Parameters::read_only(s.index)) {
      fail(hash, fmt::format("parameter #{} is read-only", s.index));
    }
  }
  if (line_.at(i) != '=') fail(i, "equal sign missing in parameter setting");
  ++i;
  s.value = real(i);
  return s;
}

}  // namespace cwe::gcode
