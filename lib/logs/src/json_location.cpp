#include "epuck2/logs/json_location.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace epuck2::logs {

namespace {

// A forgiving walk over a JSON text: it stops (returns false) at anything it does not expect
// instead of throwing, since it only runs to place an error already found.
class Scanner {
 public:
  explicit Scanner(std::string_view text) : s_(text) {}

  std::size_t pos() const { return i_; }

  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r')) ++i_;
  }

  // A string at the cursor, decoded well enough to compare keys (\uXXXX kept as written).
  bool string(std::string* out) {
    if (i_ >= s_.size() || s_[i_] != '"') return false;
    ++i_;
    while (i_ < s_.size()) {
      const char c = s_[i_++];
      if (c == '"') return true;
      if (c != '\\') {
        if (out) *out += c;
        continue;
      }
      if (i_ >= s_.size()) return false;
      const char e = s_[i_++];
      if (!out) continue;
      switch (e) {
        case 'n': *out += '\n'; break;
        case 't': *out += '\t'; break;
        case 'r': *out += '\r'; break;
        case 'b': *out += '\b'; break;
        case 'f': *out += '\f'; break;
        case 'u': *out += "\\u"; break;
        default: *out += e;
      }
    }
    return false;
  }

  bool value() {
    ws();
    if (i_ >= s_.size()) return false;
    const char c = s_[i_];
    if (c == '"') return string(nullptr);
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++i_;
      ws();
      if (i_ < s_.size() && s_[i_] == close) {
        ++i_;
        return true;
      }
      while (true) {
        if (c == '{') {
          ws();
          if (!string(nullptr)) return false;
          ws();
          if (i_ >= s_.size() || s_[i_] != ':') return false;
          ++i_;
        }
        if (!value()) return false;
        ws();
        if (i_ >= s_.size()) return false;
        if (s_[i_] == ',') {
          ++i_;
          continue;
        }
        if (s_[i_] != close) return false;
        ++i_;
        return true;
      }
    }
    // A number or a literal: up to the next delimiter.
    const std::size_t start = i_;
    while (i_ < s_.size() && std::string_view(",]} \t\r\n").find(s_[i_]) == std::string_view::npos) ++i_;
    return i_ > start;
  }

  // Moves the cursor to the value of member `key` of the object at the cursor.
  bool member(const std::string& key) {
    ws();
    if (i_ >= s_.size() || s_[i_] != '{') return false;
    ++i_;
    while (true) {
      ws();
      if (i_ < s_.size() && s_[i_] == '}') return false;
      std::string k;
      if (!string(&k)) return false;
      ws();
      if (i_ >= s_.size() || s_[i_] != ':') return false;
      ++i_;
      ws();
      if (k == key) return true;
      if (!value()) return false;
      ws();
      if (i_ >= s_.size() || s_[i_] != ',') return false;
      ++i_;
    }
  }

  // Moves the cursor to element `index` of the array at the cursor.
  bool element(std::size_t index) {
    ws();
    if (i_ >= s_.size() || s_[i_] != '[') return false;
    ++i_;
    for (std::size_t k = 0;; ++k) {
      ws();
      if (i_ < s_.size() && s_[i_] == ']') return false;
      if (k == index) return true;
      if (!value()) return false;
      ws();
      if (i_ >= s_.size() || s_[i_] != ',') return false;
      ++i_;
    }
  }

  bool at_object() const { return i_ < s_.size() && s_[i_] == '{'; }
  bool at_array() const { return i_ < s_.size() && s_[i_] == '['; }

 private:
  std::string_view s_;
  std::size_t i_ = 0;
};

std::vector<std::string> pointer_tokens(std::string_view pointer) {
  std::vector<std::string> tokens;
  if (pointer.empty()) return tokens;
  std::size_t start = 1;  // after the leading '/'
  while (true) {
    const std::size_t slash = pointer.find('/', start);
    std::string raw(pointer.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start));
    std::string token;
    for (std::size_t k = 0; k < raw.size(); ++k) {
      if (raw[k] == '~' && k + 1 < raw.size() && (raw[k + 1] == '0' || raw[k + 1] == '1')) {
        token += raw[k + 1] == '0' ? '~' : '/';
        ++k;
      } else {
        token += raw[k];
      }
    }
    tokens.push_back(token);
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  return tokens;
}

bool is_index(const std::string& t) {
  if (t.empty() || t.size() > 9) return false;
  for (const char c : t)
    if (c < '0' || c > '9') return false;
  return true;
}

}  // namespace

SourcePos position_of(std::string_view text, std::size_t offset) {
  SourcePos p{1, 1};
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) {
      ++p.line;
      p.column = 1;
    } else if (text[i] != '\r') {
      ++p.column;
    }
  }
  return p;
}

SourcePos locate_json_pointer(std::string_view text, std::string_view pointer) {
  if (!pointer.empty() && pointer.front() != '/') return {};
  const std::size_t base = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  Scanner walk(text.substr(base));
  walk.ws();
  if (walk.pos() >= text.size() - base) return {};  // no document
  for (const std::string& token : pointer_tokens(pointer)) {
    if (walk.at_object()) {
      if (!walk.member(token)) return {};
    } else if (walk.at_array() && is_index(token)) {
      if (!walk.element(static_cast<std::size_t>(std::stoul(token)))) return {};
    } else {
      return {};
    }
  }
  walk.ws();
  return position_of(text, base + walk.pos());
}

SourcePos locate_json_overflow(std::string_view text) {
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
      continue;
    }
    if (c != '-' && (c < '0' || c > '9')) continue;
    std::size_t end = i;
    while (end < text.size() && std::string_view("+-0123456789.eE").find(text[end]) != std::string_view::npos) ++end;
    const std::string number(text.substr(i, end - i));
    if (std::isinf(std::strtod(number.c_str(), nullptr))) return position_of(text, i);
    i = end - 1;
  }
  return {};
}

InputError json_error(const std::string& path, std::string_view text, const std::string& pointer,
                      const std::string& message) {
  const std::string where = " (at JSON path " + (pointer.empty() ? std::string("/") : pointer) + ")";
  std::string p = pointer;
  while (true) {
    const SourcePos at = locate_json_pointer(text, p);
    if (at.line > 0) return InputError(path, at.line, at.column, message + where);
    if (p.empty()) break;
    p.erase(p.rfind('/'));
  }
  return InputError(path, 0, 0, message + where);
}

InputError json_file_error(const std::string& path, const std::string& pointer, const std::string& message) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  if (in) ss << in.rdbuf();
  return json_error(path, ss.str(), pointer, message);
}

}  // namespace epuck2::logs
