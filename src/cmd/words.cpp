#include "cmd/words.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "cmd/value.hpp"
#include "core/error.hpp"

namespace demlab::cmd {

namespace {

ListSplitter& splitterSlot() {
  static ListSplitter s;
  return s;
}

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

// Appends the character(s) the backslash sequence at text[i] stands for and advances i past
// it. Follows Tcl_Backslash for the common sequences (\n \t ..., \xHH, \uHHHH, octal, \<newline>).
void backslash(std::string_view text, std::size_t& i, std::string& out) {
  ++i;  // the backslash
  if (i >= text.size()) {
    out += '\\';
    return;
  }
  char c = text[i++];
  auto hex = [&](int maxDigits) {
    unsigned v = 0;
    int n = 0;
    while (n < maxDigits && i < text.size() && std::isxdigit(static_cast<unsigned char>(text[i]))) {
      char h = text[i++];
      v = v * 16 + unsigned(std::isdigit(static_cast<unsigned char>(h))
                                ? h - '0'
                                : (std::tolower(h) - 'a' + 10));
      ++n;
    }
    return std::pair{v, n};
  };
  auto utf8 = [&](unsigned cp) {
    if (cp < 0x80) {
      out += char(cp);
    } else if (cp < 0x800) {
      out += char(0xC0 | (cp >> 6));
      out += char(0x80 | (cp & 0x3F));
    } else {
      out += char(0xE0 | (cp >> 12));
      out += char(0x80 | ((cp >> 6) & 0x3F));
      out += char(0x80 | (cp & 0x3F));
    }
  };
  switch (c) {
    case 'a':
      out += '\a';
      return;
    case 'b':
      out += '\b';
      return;
    case 'f':
      out += '\f';
      return;
    case 'n':
      out += '\n';
      return;
    case 'r':
      out += '\r';
      return;
    case 't':
      out += '\t';
      return;
    case 'v':
      out += '\v';
      return;
    case 'x': {
      auto [v, n] = hex(2);
      if (n == 0)
        out += 'x';
      else
        out += char(v);
      return;
    }
    case 'u': {
      auto [v, n] = hex(4);
      if (n == 0)
        out += 'u';
      else
        utf8(v);
      return;
    }
    case '\n':
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
      out += ' ';
      return;
    default:
      if (c >= '0' && c <= '7') {
        unsigned v = unsigned(c - '0');
        for (int n = 1; n < 3 && i < text.size() && text[i] >= '0' && text[i] <= '7'; ++n)
          v = v * 8 + unsigned(text[i++] - '0');
        out += char(v & 0xFF);
        return;
      }
      out += c;
  }
}

bool builtinSplit(std::string_view text, std::vector<std::string>& out, std::string& error) {
  std::size_t i = 0, n = text.size();
  while (true) {
    while (i < n && isSpace(text[i])) ++i;
    if (i >= n) return true;
    std::string elem;
    if (text[i] == '{') {
      int depth = 1;
      std::size_t start = ++i;
      while (i < n && depth > 0) {
        if (text[i] == '\\' && i + 1 < n) {
          i += 2;
          continue;
        }
        if (text[i] == '{')
          ++depth;
        else if (text[i] == '}')
          --depth;
        ++i;
      }
      if (depth > 0) {
        error = "unmatched open brace in list";
        return false;
      }
      elem.assign(text.substr(start, i - 1 - start));
      if (i < n && !isSpace(text[i])) {
        error = "list element in braces followed by \"" + std::string(text.substr(i, 20)) +
                "\" instead of space";
        return false;
      }
    } else if (text[i] == '"') {
      ++i;
      bool closed = false;
      while (i < n) {
        if (text[i] == '\\') {
          backslash(text, i, elem);
        } else if (text[i] == '"') {
          ++i;
          closed = true;
          break;
        } else {
          elem += text[i++];
        }
      }
      if (!closed) {
        error = "unmatched open quote in list";
        return false;
      }
      if (i < n && !isSpace(text[i])) {
        error = "list element in quotes followed by \"" + std::string(text.substr(i, 20)) +
                "\" instead of space";
        return false;
      }
    } else {
      while (i < n && !isSpace(text[i])) {
        if (text[i] == '\\')
          backslash(text, i, elem);
        else
          elem += text[i++];
      }
    }
    out.push_back(std::move(elem));
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

}  // namespace

void setListSplitter(ListSplitter splitter) {
  splitterSlot() = std::move(splitter);
}

std::vector<std::string> splitList(std::string_view text) {
  std::vector<std::string> out;
  std::string error;
  bool ok = splitterSlot() ? splitterSlot()(text, out, error) : builtinSplit(text, out, error);
  if (!ok) throw Error(error, {"VALUE", "LIST"});
  return out;
}

std::string quoteElement(std::string_view s) {
  if (s.empty()) return "{}";
  bool needs = s.front() == '#' || s.front() == '{' || s.front() == '"';
  bool braceable = true;
  int depth = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    char c = s[k];
    if (isSpace(c) || c == ';' || c == '$' || c == '[' || c == ']' || c == '"' || c == '\\' ||
        c == '{' || c == '}')
      needs = true;
    if (c == '{') ++depth;
    if (c == '}' && --depth < 0) braceable = false;
    if (c == '\\') braceable = false;
  }
  if (!needs) return std::string(s);
  if (braceable && depth == 0 && s.back() != '\\') {
    std::string out;
    out.reserve(s.size() + 2);
    out += '{';
    out += s;
    out += '}';
    return out;
  }
  std::string out;
  for (char c : s) {
    switch (c) {
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case ' ':
      case ';':
      case '$':
      case '[':
      case ']':
      case '"':
      case '\\':
      case '{':
      case '}':
        out += '\\';
        out += c;
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string joinList(const std::vector<std::string>& words) {
  std::string out;
  for (std::size_t k = 0; k < words.size(); ++k) {
    if (k) out += ' ';
    out += quoteElement(words[k]);
  }
  return out;
}

bool readInt(std::string_view text, std::int64_t& out) {
  std::string_view s = trim(text);
  if (s.empty()) return false;
  bool neg = false;
  if (s.front() == '+' || s.front() == '-') {
    neg = s.front() == '-';
    s.remove_prefix(1);
  }
  int base = 10;
  if (s.size() > 2 && s[0] == '0') {
    char b = char(std::tolower(s[1]));
    if (b == 'x')
      base = 16;
    else if (b == 'o')
      base = 8;
    else if (b == 'b')
      base = 2;
    if (base != 10) s.remove_prefix(2);
  }
  if (s.empty() || s.front() == '+' || s.front() == '-') return false;
  std::uint64_t v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v, base);
  if (ec != std::errc() || p != s.data() + s.size()) return false;
  if (neg) {
    if (v > std::uint64_t(INT64_MAX) + 1) return false;
    out = v == std::uint64_t(INT64_MAX) + 1 ? INT64_MIN : -std::int64_t(v);
  } else {
    if (v > std::uint64_t(INT64_MAX)) return false;
    out = std::int64_t(v);
  }
  return true;
}

bool readReal(std::string_view text, double& out) {
  std::string_view s = trim(text);
  if (s.empty()) return false;
  std::int64_t i;
  if (readInt(s, i)) {
    out = double(i);
    return true;
  }
  std::string_view body = s;
  bool neg = false;
  if (body.front() == '+' || body.front() == '-') {
    neg = body.front() == '-';
    body.remove_prefix(1);
  }
  auto lower = [](std::string_view a) {
    std::string r(a);
    for (char& c : r) c = char(std::tolower(static_cast<unsigned char>(c)));
    return r;
  };
  std::string l = lower(body);
  if (l == "inf" || l == "infinity") {
    out = neg ? -INFINITY : INFINITY;
    return true;
  }
  if (l == "nan") {
    out = NAN;
    return true;
  }
  if (body.empty() ||
      !(std::isdigit(static_cast<unsigned char>(body.front())) || body.front() == '.'))
    return false;
  double v = 0;
  auto [p, ec] = std::from_chars(body.data(), body.data() + body.size(), v);
  if (p != body.data() + body.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    // Tcl reads overflow as Inf and underflow as 0, as strtod does.
    v = std::strtod(std::string(body).c_str(), nullptr);
  } else if (ec != std::errc()) {
    return false;
  }
  out = neg ? -v : v;
  return true;
}

bool readBool(std::string_view text, bool& out) {
  std::string s(trim(text));
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  std::int64_t i;
  if (readInt(s, i)) {
    out = i != 0;
    return true;
  }
  if (s.empty()) return false;
  auto prefixOf = [&](std::string_view word, std::size_t minLen) {
    return s.size() >= minLen && s.size() <= word.size() && word.substr(0, s.size()) == s;
  };
  if (prefixOf("true", 1) || prefixOf("yes", 1) || s == "on") {
    out = true;
    return true;
  }
  if (prefixOf("false", 1) || prefixOf("no", 1) || prefixOf("off", 2)) {
    out = false;
    return true;
  }
  return false;
}

std::string formatReal(double x) {
  if (std::isnan(x)) return "NaN";
  if (std::isinf(x)) return x > 0 ? "Inf" : "-Inf";
  // The shortest digits that read back to x, laid out as Tcl does (TclPrintDouble with
  // tcl_precision 0): exponential below 1e-4 and from 1e17 on, fixed with ".0" otherwise.
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  std::string sci(buf, p);
  std::size_t e = sci.find('e');
  int exp10 = std::atoi(sci.c_str() + e + 1);
  std::string mant = sci.substr(0, e);
  bool neg = mant[0] == '-';
  if (neg) mant.erase(0, 1);
  std::string digits;
  for (char c : mant)
    if (c != '.') digits += c;
  std::string out;
  if (exp10 < -4 || exp10 > 16) {
    out = digits.substr(0, 1);
    if (digits.size() > 1) out += "." + digits.substr(1);
    out += exp10 < 0 ? "e-" : "e+";
    out += std::to_string(std::abs(exp10));
  } else if (exp10 < 0) {
    out = "0." + std::string(std::size_t(-exp10 - 1), '0') + digits;
  } else {
    if (digits.size() <= std::size_t(exp10) + 1) {
      out = digits + std::string(std::size_t(exp10) + 1 - digits.size(), '0') + ".0";
    } else {
      out = digits.substr(0, std::size_t(exp10) + 1) + "." + digits.substr(std::size_t(exp10) + 1);
    }
  }
  return neg ? "-" + out : out;
}

std::size_t helpWidth() {
  std::size_t w = 0;
  if (const char* c = std::getenv("COLUMNS")) {
    std::int64_t n;
    if (readInt(c, n) && n > 0 && n < 100000) w = static_cast<std::size_t>(n);
  }
  winsize ws{};
  if (w == 0 && isatty(1) && ioctl(1, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) w = ws.ws_col;
  if (w == 0) w = 80;
  return std::max<std::size_t>(w, 40);
}

std::string wrapText(std::string_view text, std::size_t width, std::size_t indent,
                     std::size_t first) {
  // A newline in the text ends a line (a paragraph or a list item of the declaration).
  if (const std::size_t nl = text.find('\n'); nl != std::string_view::npos) {
    return wrapText(text.substr(0, nl), width, indent, first) +
           wrapText(text.substr(nl + 1), width, indent, indent);
  }
  std::string out, line(first, ' ');
  std::size_t words = 0;
  std::size_t k = 0;
  while (k < text.size()) {
    const std::size_t start = text.find_first_not_of(' ', k);
    if (start == std::string_view::npos) break;
    std::size_t end = text.find(' ', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(start, end - start);
    if (words > 0 && line.size() + 1 + word.size() > width) {
      out += line + "\n";
      line.assign(indent, ' ');
      words = 0;
    }
    if (words > 0) line += ' ';
    line += word;
    ++words;
    k = end;
  }
  return out + line + "\n";
}

std::string helpRow(std::string_view left, std::size_t leftWidth, std::string_view right,
                    std::size_t width) {
  const std::size_t column = 4 + leftWidth + 2;
  if (column + 30 > width) return "    " + std::string(left) + "\n" + wrapText(right, width, 8, 8);
  std::string text = wrapText(right, width, column, column);
  return text.replace(0, column,
                      "    " + std::string(left) + std::string(leftWidth - left.size() + 2, ' '));
}

std::string alternatives(const std::vector<std::string>& items, std::string_view conj) {
  std::string out;
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (k) {
      if (items.size() > 2) out += ",";
      out += " ";
      if (k + 1 == items.size()) {
        out += conj;
        out += " ";
      }
    }
    out += items[k];
  }
  return out;
}

std::string codeWord(std::string_view name) {
  std::string out;
  for (char c : name)
    if (c != '-' && c != '_') out += char(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string toString(const Value& v) {
  struct Visitor {
    std::string operator()(std::monostate) const { return ""; }
    std::string operator()(bool b) const { return b ? "1" : "0"; }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(double d) const { return formatReal(d); }
    std::string operator()(const std::string& s) const { return s; }
    std::string operator()(const List& l) const {
      std::vector<std::string> w;
      for (const Value& e : l) w.push_back(toString(e));
      return joinList(w);
    }
    std::string operator()(const Dict& d) const {
      std::vector<std::string> w;
      for (const auto& [k, e] : d) {
        w.push_back(k);
        w.push_back(toString(e));
      }
      return joinList(w);
    }
    // Each byte as the character of that code, as Tcl shows a byte array.
    std::string operator()(const Bytes& b) const {
      std::string out;
      for (std::uint8_t c : b.data) {
        if (c < 0x80) {
          out += char(c);
        } else {
          out += char(0xc0 | (c >> 6));
          out += char(0x80 | (c & 0x3f));
        }
      }
      return out;
    }
    std::string operator()(const Ints& l) const {
      std::string out;
      for (std::size_t k = 0; k < l.data.size(); ++k) {
        if (k) out += ' ';
        out += std::to_string(l.data[k]);
      }
      return out;
    }
    std::string operator()(const Reals& r) const {
      std::string out;
      if (r.stride <= 0) {
        for (std::size_t k = 0; k < r.data.size(); ++k) {
          if (k) out += ' ';
          out += formatReal(r.data[k]);
        }
        return out;
      }
      for (std::size_t k = 0; k < r.data.size(); k += std::size_t(r.stride)) {
        if (k) out += ' ';
        out += '{';
        for (int j = 0; j < r.stride; ++j) {
          if (j) out += ' ';
          out += formatReal(r.data[k + std::size_t(j)]);
        }
        out += '}';
      }
      return out;
    }
  };
  return std::visit(Visitor{}, v.v);
}

}  // namespace demlab::cmd
