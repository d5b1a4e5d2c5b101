// What Emscripten 3.1.6's libc++ 13 lacks of the C++20 library the engine uses (g++ 12's
// libstdc++ has it all): floating-point std::to_chars / std::from_chars and std::bit_cast.
// Force-included (-include) in the WebAssembly build only (web/wasm_dependencies.cmake), so the
// engine's sources stay as they are and the native build never sees this file. Each piece is
// declared only when the library does not provide it (its feature-test macro).
//
//   to_chars(first, last, v)    the shortest text that reads back to v, plain or scientific
//                               whichever is shorter (plain on a tie), exponent of two digits at
//                               least ("1e-06"), as the standard says. Found by trying 1, 2, ...
//                               significant digits ("%.*e", read back with strtod): the
//                               correctly rounded p-digit decimal is the nearest one, so it
//                               reads back whenever any p-digit decimal does.
//   from_chars(first, last, v)  general format: strtod (the "C" locale, correctly rounded) after
//                               refusing what from_chars refuses and strtod takes (leading space,
//                               '+', hexadecimal).
//   bit_cast<To>(from)          __builtin_bit_cast.
#pragma once

#ifdef __cplusplus
#include <charconv>
#include <version>

#if !defined(__cpp_lib_to_chars)
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <system_error>

namespace maille::web_compat {

template <class T>
std::to_chars_result shortest_chars(char* first, char* last, T v) {
  char sci[48];
  int p = 1;
  for (; p < 17; ++p) {
    std::snprintf(sci, sizeof sci, "%.*e", p - 1, double(v));
    if (static_cast<T>(std::strtod(sci, nullptr)) == v) break;
  }
  std::snprintf(sci, sizeof sci, "%.*e", p - 1, double(v));
  std::string s(sci), out;
  const std::size_t e = s.find('e');
  if (e == std::string::npos) {
    out = s;  // inf, -inf, nan
  } else {
    const bool negative = s[0] == '-';
    std::string digits;
    for (std::size_t i = negative ? 1 : 0; i < e; ++i)
      if (s[i] != '.') digits += s[i];
    const int exponent = std::atoi(s.c_str() + e + 1);
    std::string scientific = digits.substr(0, 1);
    if (digits.size() > 1) scientific += "." + digits.substr(1);
    char ex[8];
    std::snprintf(ex, sizeof ex, "e%c%02d", exponent < 0 ? '-' : '+',
                  exponent < 0 ? -exponent : exponent);
    scientific += ex;
    const int n = int(digits.size());
    std::string plain;
    if (exponent < 0)
      plain = "0." + std::string(std::size_t(-exponent - 1), '0') + digits;
    else if (exponent + 1 >= n)
      plain = digits + std::string(std::size_t(exponent + 1 - n), '0');
    else
      plain = digits.substr(0, std::size_t(exponent + 1)) + "." +
              digits.substr(std::size_t(exponent + 1));
    out = (negative ? "-" : "") + (plain.size() <= scientific.size() ? plain : scientific);
  }
  if (out.size() > std::size_t(last - first)) return {last, std::errc::value_too_large};
  std::memcpy(first, out.data(), out.size());
  return {first + out.size(), std::errc()};
}

template <class T>
std::from_chars_result parse(const char* first, const char* last, T& value) {
  const std::string text(first, last);
  if (text.empty() || text[0] == '+' || text[0] == ' ' || text[0] == '\t' || text[0] == '\n' ||
      text.find_first_of("xX") != std::string::npos)
    return {first, std::errc::invalid_argument};
  char* end = nullptr;
  errno = 0;
  const double r = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return {first, std::errc::invalid_argument};
  const char* ptr = first + (end - text.c_str());
  if (errno == ERANGE) return {ptr, std::errc::result_out_of_range};
  value = static_cast<T>(r);
  return {ptr, std::errc()};
}

}  // namespace maille::web_compat

namespace std {
inline to_chars_result to_chars(char* first, char* last, double v) {
  return maille::web_compat::shortest_chars(first, last, v);
}
inline to_chars_result to_chars(char* first, char* last, float v) {
  return maille::web_compat::shortest_chars(first, last, v);
}
inline from_chars_result from_chars(const char* first, const char* last, double& v,
                                    chars_format = chars_format::general) {
  return maille::web_compat::parse(first, last, v);
}
inline from_chars_result from_chars(const char* first, const char* last, float& v,
                                    chars_format = chars_format::general) {
  return maille::web_compat::parse(first, last, v);
}
}  // namespace std
#endif  // !__cpp_lib_to_chars

#if !defined(__cpp_lib_bit_cast)
namespace std {
template <class To, class From>
constexpr To bit_cast(const From& from) noexcept {
  static_assert(sizeof(To) == sizeof(From));
  return __builtin_bit_cast(To, from);
}
}  // namespace std
#endif  // !__cpp_lib_bit_cast
#endif  // __cplusplus
