#pragma once
// Exceptions of the core library. Each carries a message written for the user: what was wrong,
// with which value, and what would be right.
#include <stdexcept>
#include <string>

namespace rtabmap {

// Base of every error the core throws on bad input or a failed resource.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A parameter key, type or value is invalid (see params/Parameters.h).
class ParameterError : public Error {
 public:
  using Error::Error;
};

// Malformed outside data: a file, a message, a string that does not parse.
class FormatError : public Error {
 public:
  using Error::Error;
};

// The long-term memory (SQLite database) cannot be opened, read or written.
class DatabaseError : public Error {
 public:
  using Error::Error;
};

}  // namespace rtabmap
