#include "cwe/core/json_input.hpp"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe {
namespace {

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1,
// column 2: " prefix (the location is given as source:line:col instead).
std::string detail(const nlohmann::json::exception& e) {
  std::string text = e.what();
  if (const std::size_t tag = text.find("] "); text.starts_with("[") && tag != text.npos) {
    text.erase(0, tag + 2);
  }
  if (text.starts_with("parse error")) {
    if (const std::size_t colon = text.find(": "); colon != text.npos) text.erase(0, colon + 2);
  }
  return text;
}

// The offset of the n-th (from 1) occurrence of `needle` in `text` as a key ("needle" then
// blanks and ':'), or npos.
std::size_t nth_key(std::string_view text, const std::string& key, int n) {
  const std::string quoted = "\"" + key + "\"";
  for (std::size_t at = text.find(quoted); at != text.npos; at = text.find(quoted, at + 1)) {
    std::size_t after = at + quoted.size();
    while (after < text.size() && (text[after] == ' ' || text[after] == '\t' ||
                                   text[after] == '\n' || text[after] == '\r')) {
      ++after;
    }
    if (after < text.size() && text[after] == ':' && --n == 0) return at;
  }
  return text.npos;
}

struct DuplicateKey {
  std::string key;
  int occurrence = 0;  // of the key as a key in the text, from 1
};

}  // namespace

nlohmann::json parse_json_input(std::string_view text, const std::string& source) {
  // Keys of the objects being read (one set per open object), and how often each key has been
  // seen in the text so far, to place a duplicate.
  std::vector<std::vector<std::string>> open;
  std::map<std::string, int> seen;
  const auto callback = [&](int, nlohmann::json::parse_event_t event, nlohmann::json& value) {
    switch (event) {
      case nlohmann::json::parse_event_t::object_start:
        open.emplace_back();
        break;
      case nlohmann::json::parse_event_t::object_end:
        if (!open.empty()) open.pop_back();
        break;
      case nlohmann::json::parse_event_t::key: {
        const std::string key = value.get<std::string>();
        const int occurrence = ++seen[key];
        if (!open.empty()) {
          std::vector<std::string>& keys = open.back();
          for (const std::string& k : keys) {
            if (k == key) throw DuplicateKey{key, occurrence};
          }
          keys.push_back(key);
        }
        break;
      }
      default:
        break;
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, callback);
  } catch (const DuplicateKey& d) {
    const std::size_t at = nth_key(text, d.key, d.occurrence);
    throw InputError(at == text.npos ? SourceLocation{source} : location_of(text, at, source),
                     "key \"" + d.key + "\" written twice in one object: keep one");
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(location_of(text, e.byte > 0 ? e.byte - 1 : 0, source),
                     "not valid JSON: " + detail(e));
  } catch (const nlohmann::json::exception& e) {
    // A number beyond double range (1e400) carries no position; its text is in the message.
    std::string message = detail(e);
    SourceLocation where{source};
    const std::size_t open_quote = message.find('\'');
    const std::size_t close_quote = message.rfind('\'');
    if (open_quote != message.npos && close_quote > open_quote + 1) {
      const std::size_t at =
          text.find(message.substr(open_quote + 1, close_quote - open_quote - 1));
      if (at != text.npos) where = location_of(text, at, source);
    }
    throw InputError(where, "not valid JSON: " + message);
  }
}

std::string json_pointer_token(std::string_view key) {
  std::string token;
  for (const char c : key) {
    if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  return token;
}

namespace {

// A walk over valid JSON text noting where each value starts.
class PlaceScanner {
 public:
  PlaceScanner(std::string_view text, std::map<std::string, std::pair<int, int>, std::less<>>& out)
      : text_(text), out_(out) {}

  void run() {
    blanks();
    if (i_ < text_.size()) value("", 0);
  }

 private:
  void blanks() {
    while (i_ < text_.size() &&
           (text_[i_] == ' ' || text_[i_] == '\t' || text_[i_] == '\n' || text_[i_] == '\r')) {
      ++i_;
    }
  }

  // The line and column of offset i_ (offsets only grow, so the count goes on from the last).
  std::pair<int, int> here() {
    for (; counted_ < i_ && counted_ < text_.size(); ++counted_) {
      if (text_[counted_] == '\n') {
        ++line_;
        column_ = 1;
      } else {
        ++column_;
      }
    }
    return {line_, column_};
  }

  // A string starting at i_ ('"'), its raw text between the quotes (escapes kept: keys with
  // escapes are rare in these files, and such a key is then simply not found).
  std::string_view string() {
    const std::size_t start = ++i_;
    while (i_ < text_.size() && text_[i_] != '"') i_ += text_[i_] == '\\' ? 2 : 1;
    const std::string_view body = text_.substr(start, std::min(i_, text_.size()) - start);
    ++i_;
    return body;
  }

  // Skips a value nested too deep to index, without recursion.
  void skip() {
    int depth = 0;
    do {
      if (i_ >= text_.size()) return;
      const char c = text_[i_];
      if (c == '"') {
        string();
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if (c == '}' || c == ']') --depth;
      ++i_;
    } while (depth > 0);
  }

  void value(const std::string& pointer, int depth) {
    out_.emplace(pointer, here());
    if (i_ >= text_.size()) return;
    const char c = text_[i_];
    if ((c == '{' || c == '[') && depth >= JsonPlaces::kDepth) {
      skip();
      return;
    }
    if (c == '{') {
      ++i_;
      blanks();
      while (i_ < text_.size() && text_[i_] != '}') {
        const std::string key = json_pointer_token(string());
        blanks();
        ++i_;  // ':'
        blanks();
        value(pointer + "/" + key, depth + 1);
        blanks();
        if (i_ < text_.size() && text_[i_] == ',') ++i_;
        blanks();
      }
      ++i_;
    } else if (c == '[') {
      ++i_;
      blanks();
      for (std::size_t k = 0; i_ < text_.size() && text_[i_] != ']'; ++k) {
        value(pointer + "/" + std::to_string(k), depth + 1);
        blanks();
        if (i_ < text_.size() && text_[i_] == ',') ++i_;
        blanks();
      }
      ++i_;
    } else if (c == '"') {
      string();
    } else {
      while (i_ < text_.size() && text_[i_] != ',' && text_[i_] != '}' && text_[i_] != ']' &&
             text_[i_] != ' ' && text_[i_] != '\t' && text_[i_] != '\n' && text_[i_] != '\r') {
        ++i_;
      }
    }
  }

  std::string_view text_;
  std::map<std::string, std::pair<int, int>, std::less<>>& out_;
  std::size_t i_ = 0;
  std::size_t counted_ = 0;
  int line_ = 1;
  int column_ = 1;
};

}  // namespace

JsonPlaces::JsonPlaces(std::string_view text, std::string source) : source_(std::move(source)) {
  PlaceScanner(text, places_).run();
}

SourceLocation JsonPlaces::at(const std::string& pointer) const {
  const auto found = places_.find(pointer);
  if (found == places_.end()) return SourceLocation{source_};
  return SourceLocation{source_, found->second.first, found->second.second};
}

}  // namespace cwe
