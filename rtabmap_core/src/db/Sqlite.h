#pragma once
// Thin RAII layer over the SQLite C API for the long-term memory: a connection that caches its
// prepared statements, statements with typed binds and columns, and a transaction guard.
// Every failure becomes a DatabaseError naming the database path, what we were doing and
// SQLite's own message. Private to the db area: SQLite never appears in public headers.
#include <sqlite3.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "rtabmap_core/codec/Compression.h"

namespace rtabmap::db {

class Connection;

class Statement {
 public:
  Statement(Connection& connection, const std::string& sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters are 1-based, as in SQL.
  Statement& bindNull(int index);
  Statement& bind(int index, int value);
  Statement& bind(int index, int64_t value);
  Statement& bind(int index, double value);
  Statement& bind(int index, const std::string& text);
  // Empty bytes bind NULL: "no data" is NULL in every column of the schema. The bytes must
  // outlive step() (bound without copy).
  Statement& bindBlob(int index, const Bytes& bytes);
  Statement& bindBlob(int index, const void* data, size_t size);

  // Runs one step: true while a row is available, false when done.
  bool step();
  // Steps a statement that returns no row (INSERT, UPDATE...).
  void run();
  void reset();

  // Columns are 0-based, as in the SQLite API.
  bool isNull(int column) const;
  int columnInt(int column) const;
  int64_t columnInt64(int column) const;
  double columnDouble(int column) const;
  std::string columnText(int column) const;
  // Pointer valid until the next step/reset; size 0 for NULL.
  const unsigned char* columnBlob(int column, size_t* size) const;
  Bytes columnBytes(int column) const;

  const std::string& sql() const { return sql_; }

 private:
  void check(int rc, const char* what) const;

  Connection& connection_;
  sqlite3_stmt* stmt_ = nullptr;
  std::string sql_;
};

// A cached statement in use; resets it (and clears its bindings) when the scope ends, so a
// statement left half-stepped by an exception never keeps a read snapshot open.
class Query {
 public:
  explicit Query(Statement& statement) : statement_(statement) {}
  ~Query() { statement_.reset(); }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  Statement* operator->() { return &statement_; }
  Statement& operator*() { return statement_; }

 private:
  Statement& statement_;
};

class Connection {
 public:
  // flags: SQLITE_OPEN_* (SQLITE_OPEN_URI is added when `path` is a "file:" URI).
  Connection(const std::string& path, int flags, const std::string& displayPath);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // Runs SQL without parameters (may hold several statements: the schema, pragmas).
  void exec(const std::string& sql);
  // A prepared statement from this connection's cache (prepared on first use).
  Query query(const std::string& sql);
  // Single integer result of a query without parameters (PRAGMA user_version, count(*)...);
  // `fallback` if it returns no row or NULL.
  int64_t scalar(const std::string& sql, int64_t fallback = 0);

  bool isReadOnly() const;
  sqlite3* handle() const { return db_; }
  // The path shown in messages (the file path, not the URI).
  const std::string& path() const { return displayPath_; }

  // Throws DatabaseError "<path>: <what>: <sqlite message> (<code name>)"; SQLITE_FULL gets a
  // message that says the disk (or the page limit) is full.
  [[noreturn]] void fail(int rc, const std::string& what) const;

 private:
  sqlite3* db_ = nullptr;
  std::string displayPath_;
  std::map<std::string, std::unique_ptr<Statement>> cache_;
};

// BEGIN IMMEDIATE ... COMMIT; rolls back when destroyed uncommitted (exception path).
// IMMEDIATE takes the write lock at once, so a busy database fails here rather than midway.
class Transaction {
 public:
  explicit Transaction(Connection& connection);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit();

 private:
  Connection& connection_;
  bool open_ = true;
};

// A read transaction (BEGIN ... COMMIT, deferred): the statements inside see one snapshot of
// the database. Under WAL it never blocks the writer.
class ReadTransaction {
 public:
  explicit ReadTransaction(Connection& connection);
  ~ReadTransaction();
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;

 private:
  Connection& connection_;
};

}  // namespace rtabmap::db
