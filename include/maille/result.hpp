// Result<T>: a value or an error that says where the input was wrong.
#pragma once

#include <string>
#include <utility>
#include <variant>

namespace maille {

// An error in user input, located: "scene.toml:12:3: key 'mass': must be > 0 (got -1)".
struct InputError {
  std::string file;
  int line = 0;     // 1-based; 0 when the error is not tied to a line
  int column = 0;   // 1-based
  std::string key;  // dotted path of the offending key, e.g. "flag[0].mass"
  std::string message;

  std::string to_string() const;
};

template <class T>
class Result {
 public:
  Result(T value) : v_(std::move(value)) {}           // NOLINT: implicit by design
  Result(InputError error) : v_(std::move(error)) {}  // NOLINT
  bool ok() const { return std::holds_alternative<T>(v_); }
  explicit operator bool() const { return ok(); }
  T& value() { return std::get<T>(v_); }
  const T& value() const { return std::get<T>(v_); }
  T& operator*() { return value(); }
  T* operator->() { return &value(); }
  const InputError& error() const { return std::get<InputError>(v_); }

 private:
  std::variant<T, InputError> v_;
};

}  // namespace maille
