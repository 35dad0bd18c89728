#pragma once
/// \file
/// Numbers and points as text for messages, summaries and text files: the one set
/// of formatters every module uses. Header-only.

#include <iomanip>
#include <sstream>
#include <string>

#include "uavip/core/types.h"

namespace uavip {

/// `v` with `digits` significant digits, as a stream prints it (6 is the stream's
/// default: 0.1, 1e+12, nan).
inline std::string formatNumber(double v, int digits = 6) {
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

/// `v` with `decimals` digits after the point (1.50).
inline std::string formatFixed(double v, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << v;
  return os.str();
}

/// "(x, y, z)" in metres with two decimals: a position in a message.
inline std::string formatPoint(const Vec3& p) {
  return "(" + formatFixed(p.x(), 2) + ", " + formatFixed(p.y(), 2) + ", " + formatFixed(p.z(), 2) +
         ")";
}

/// "(x, y, z)" with 6 significant digits: a raw value that may be huge or NaN.
inline std::string formatRawPoint(const Vec3& p) {
  return "(" + formatNumber(p.x()) + ", " + formatNumber(p.y()) + ", " + formatNumber(p.z()) + ")";
}

/// `text` for inside an XML or HTML element or attribute: '&', '<', '>' and '"' as
/// entities (the mission page's title, a KML name).
inline std::string markupEscaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// `text` with every control character (bytes 0x00-0x1F and 0x7F) written as an
/// escape (\n, \r, \t, else \xNN), so that a message naming a file whose name holds
/// a newline stays one line. Other bytes (UTF-8 included) are kept.
inline std::string escapeControl(const std::string& text) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c != 0x7f) {
      out += ch;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    }
  }
  return out;
}

}  // namespace uavip
