#include "cwe/core/json_input.hpp"

#include <map>
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

}  // namespace cwe
