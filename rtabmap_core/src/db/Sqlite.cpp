#include "Sqlite.h"

#include "rtabmap_core/common/Error.h"
#include "rtabmap_core/common/Log.h"

namespace rtabmap::db {

// ------------------------------------------------------------------------------- Connection

Connection::Connection(const std::string& path, int flags, const std::string& displayPath)
    : displayPath_(displayPath) {
  if (path.rfind("file:", 0) == 0) flags |= SQLITE_OPEN_URI;
  // NOMUTEX: each connection is used by one thread at a time (the writer thread, or readers
  // under the Database's read mutex), so SQLite's own per-connection mutex is redundant.
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw DatabaseError("cannot open database " + displayPath_ + ": " + message);
  }
  sqlite3_extended_result_codes(db_, 1);
}

Connection::~Connection() {
  cache_.clear();  // statements must be finalised before the connection closes
  if (db_) {
    const int rc = sqlite3_close(db_);
    if (rc != SQLITE_OK) {
      RTABMAP_ERROR("closing database " << displayPath_ << ": " << sqlite3_errstr(rc));
      sqlite3_close_v2(db_);
    }
  }
}

void Connection::exec(const std::string& sql) {
  char* error = nullptr;
  const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    const std::string message = error ? error : sqlite3_errstr(rc);
    sqlite3_free(error);
    fail(rc, "executing \"" + sql.substr(0, 60) + "\": " + message);
  }
}

Query Connection::query(const std::string& sql) {
  auto it = cache_.find(sql);
  if (it == cache_.end()) {
    it = cache_.emplace(sql, std::make_unique<Statement>(*this, sql)).first;
  }
  return Query(*it->second);
}

int64_t Connection::scalar(const std::string& sql, int64_t fallback) {
  Query q = query(sql);
  if (!q->step() || q->isNull(0)) return fallback;
  return q->columnInt64(0);
}

bool Connection::isReadOnly() const { return sqlite3_db_readonly(db_, "main") == 1; }

void Connection::fail(int rc, const std::string& what) const {
  const int primary = rc & 0xff;
  std::string message = displayPath_ + ": " + what;
  if (primary == SQLITE_FULL) {
    throw DatabaseError(message +
                        ": the disk is full (or the database reached its page limit); what was "
                        "committed before is kept (SQLITE_FULL)");
  }
  const char* detail = db_ ? sqlite3_errmsg(db_) : nullptr;
  message += std::string(": ") + (detail ? detail : sqlite3_errstr(rc));
  message += std::string(" (") + sqlite3_errstr(rc) + ", code " + std::to_string(rc) + ")";
  if (primary == SQLITE_CORRUPT || primary == SQLITE_NOTADB) {
    message += "; the file is corrupt";
  }
  throw DatabaseError(message);
}

// -------------------------------------------------------------------------------- Statement

Statement::Statement(Connection& connection, const std::string& sql)
    : connection_(connection), sql_(sql) {
  const int rc = sqlite3_prepare_v3(connection_.handle(), sql.c_str(), -1,
                                    SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr);
  if (rc != SQLITE_OK) connection_.fail(rc, "preparing \"" + sql + "\"");
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

void Statement::check(int rc, const char* what) const {
  if (rc != SQLITE_OK) connection_.fail(rc, std::string(what) + " in \"" + sql_ + "\"");
}

Statement& Statement::bindNull(int index) {
  check(sqlite3_bind_null(stmt_, index), "binding NULL");
  return *this;
}

Statement& Statement::bind(int index, int value) {
  check(sqlite3_bind_int(stmt_, index, value), "binding an integer");
  return *this;
}

Statement& Statement::bind(int index, int64_t value) {
  check(sqlite3_bind_int64(stmt_, index, value), "binding an integer");
  return *this;
}

Statement& Statement::bind(int index, double value) {
  check(sqlite3_bind_double(stmt_, index, value), "binding a real");
  return *this;
}

Statement& Statement::bind(int index, const std::string& text) {
  check(sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()),
                          SQLITE_TRANSIENT),
        "binding text");
  return *this;
}

Statement& Statement::bindBlob(int index, const Bytes& bytes) {
  return bindBlob(index, bytes.data(), bytes.size());
}

Statement& Statement::bindBlob(int index, const void* data, size_t size) {
  if (size == 0) return bindNull(index);
  check(sqlite3_bind_blob64(stmt_, index, data, size, SQLITE_STATIC), "binding a blob");
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  connection_.fail(rc, "running \"" + sql_ + "\"");
}

void Statement::run() {
  while (step()) {
  }
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::isNull(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

int Statement::columnInt(int column) const { return sqlite3_column_int(stmt_, column); }

int64_t Statement::columnInt64(int column) const { return sqlite3_column_int64(stmt_, column); }

double Statement::columnDouble(int column) const { return sqlite3_column_double(stmt_, column); }

std::string Statement::columnText(int column) const {
  const unsigned char* text = sqlite3_column_text(stmt_, column);
  const int size = sqlite3_column_bytes(stmt_, column);
  return text ? std::string(reinterpret_cast<const char*>(text), size) : std::string();
}

const unsigned char* Statement::columnBlob(int column, size_t* size) const {
  const void* data = sqlite3_column_blob(stmt_, column);
  *size = data ? static_cast<size_t>(sqlite3_column_bytes(stmt_, column)) : 0;
  return static_cast<const unsigned char*>(data);
}

Bytes Statement::columnBytes(int column) const {
  size_t size = 0;
  const unsigned char* data = columnBlob(column, &size);
  return data ? Bytes(data, data + size) : Bytes();
}

// ------------------------------------------------------------------------------ Transaction

Transaction::Transaction(Connection& connection) : connection_(connection) {
  connection_.exec("BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
  if (!open_) return;
  // A failed statement (SQLITE_FULL, I/O) may already have rolled the transaction back; then
  // ROLLBACK itself fails harmlessly, which we ignore.
  sqlite3_exec(connection_.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
}

void Transaction::commit() {
  connection_.exec("COMMIT");
  open_ = false;
}

ReadTransaction::ReadTransaction(Connection& connection) : connection_(connection) {
  connection_.exec("BEGIN");
}

ReadTransaction::~ReadTransaction() {
  // A read transaction has nothing to commit; ending it releases the snapshot.
  sqlite3_exec(connection_.handle(), "COMMIT", nullptr, nullptr, nullptr);
}

}  // namespace rtabmap::db
