// Errors that come from data or the environment (a bad DEM, no GL context) travel as
// values; programmer errors assert. No exception crosses Polder's public API.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace polder {

enum class ErrorKind {
  InvalidArgument,  // a parameter the caller gave is out of range or malformed
  InvalidData,      // a file's content is corrupt, truncated or unusable
  Io,               // a file is missing or cannot be read or written
  Unsupported,      // a format or feature Polder does not handle
  OutOfMemory,      // the request needs more memory than is allowed or available
  Environment,      // no GL context, no display, a library failed to initialise
};

struct Error {
  ErrorKind kind = ErrorKind::InvalidData;
  std::string message;
};

// Shorthand for building errors at the point of failure.
inline Error makeError(ErrorKind kind, std::string message) { return Error{kind, std::move(message)}; }

// Either a value or an Error. A small stand-in for C++23's std::expected.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : m_state(std::move(value)) {}
  Result(Error error) : m_state(std::move(error)) {}

  bool ok() const { return std::holds_alternative<T>(m_state); }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok() && "Result::value() called on an error");
    return std::get<T>(m_state);
  }
  const T& value() const& {
    assert(ok() && "Result::value() called on an error");
    return std::get<T>(m_state);
  }
  T&& value() && {
    assert(ok() && "Result::value() called on an error");
    return std::get<T>(std::move(m_state));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const Error& error() const {
    assert(!ok() && "Result::error() called on a value");
    return std::get<Error>(m_state);
  }

 private:
  std::variant<T, Error> m_state;
};

// Result of an operation with no value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : m_error(std::move(error)), m_ok(false) {}

  bool ok() const { return m_ok; }
  explicit operator bool() const { return m_ok; }
  const Error& error() const {
    assert(!m_ok && "Status::error() called on success");
    return m_error;
  }

 private:
  Error m_error;
  bool m_ok = true;
};

}  // namespace polder
