#include "io/json_writer.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace capsim {

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (const char ch : text) {
    switch (ch) {
    case '"':
      out += "\\\"";
      break;
    case '\\':
      out += "\\\\";
      break;
    case '\n':
      out += "\\n";
      break;
    case '\r':
      out += "\\r";
      break;
    case '\t':
      out += "\\t";
      break;
    case '\b':
      out += "\\b";
      break;
    case '\f':
      out += "\\f";
      break;
    default:
      if (static_cast<unsigned char>(ch) < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned char>(ch));
        out += buf;
      } else {
        out += ch; // UTF-8 bytes pass through unchanged
      }
    }
  }
  return out + "\"";
}

std::string json_number(double v) {
  if (!std::isfinite(v))
    return "null";
  // Shortest text that reads back to the same double (0.2, not 0.20000000000000001).
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

void JsonWriter::newline() {
  out_ += "\n" + std::string(2 * stack_.size(), ' ');
}

// Emits what goes before any value: the comma and line break of an array element, or
// nothing when key() has already written `"name": `.
void JsonWriter::before_value() {
  if (stack_.empty()) {
    if (!out_.empty())
      throw std::logic_error("JsonWriter: a second top-level value");
    return;
  }
  if (have_key_) {
    have_key_ = false;
    return;
  }
  if (stack_.back().is_object)
    throw std::logic_error("JsonWriter: a value inside an object needs a key");
  if (stack_.back().count++ > 0)
    out_ += ",";
  newline();
}

void JsonWriter::raw(const std::string& text) {
  before_value();
  out_ += text;
}

void JsonWriter::key(const std::string& name) {
  if (stack_.empty() || !stack_.back().is_object || have_key_)
    throw std::logic_error("JsonWriter: key \"" + name + "\" outside an object");
  if (stack_.back().count++ > 0)
    out_ += ",";
  newline();
  out_ += json_quote(name) + ": ";
  have_key_ = true;
}

void JsonWriter::begin_object() {
  raw("{");
  stack_.push_back({true, 0});
}

void JsonWriter::begin_object(const std::string& name) {
  key(name);
  begin_object();
}

void JsonWriter::begin_array() {
  raw("[");
  stack_.push_back({false, 0});
}

void JsonWriter::begin_array(const std::string& name) {
  key(name);
  begin_array();
}

void JsonWriter::close(bool is_object) {
  if (stack_.empty() || stack_.back().is_object != is_object || have_key_)
    throw std::logic_error(is_object ? "JsonWriter: unbalanced end_object"
                                     : "JsonWriter: unbalanced end_array");
  const bool empty = stack_.back().count == 0;
  stack_.pop_back();
  if (!empty)
    newline();
  out_ += is_object ? "}" : "]";
}

void JsonWriter::end_object() {
  close(true);
}
void JsonWriter::end_array() {
  close(false);
}

void JsonWriter::value(double v) {
  raw(json_number(v));
}
void JsonWriter::value(bool v) {
  raw(v ? "true" : "false");
}
void JsonWriter::value(const std::string& v) {
  raw(json_quote(v));
}
void JsonWriter::value(const char* v) {
  raw(json_quote(v));
}
void JsonWriter::null() {
  raw("null");
}

void JsonWriter::field(const std::string& name, const std::vector<double>& v) {
  std::string text = "[";
  for (std::size_t i = 0; i < v.size(); ++i)
    text += (i ? ", " : "") + json_number(v[i]);
  key(name);
  raw(text + "]");
}

void JsonWriter::matrix(const std::string& name, const Mat3& m) {
  std::string text = "[";
  for (int i = 0; i < 3; ++i) {
    text += i ? ", [" : "[";
    for (int j = 0; j < 3; ++j)
      text += (j ? ", " : "") + json_number(m.m[i][j]);
    text += "]";
  }
  key(name);
  raw(text + "]");
}

std::string JsonWriter::str() const {
  if (!stack_.empty() || have_key_)
    throw std::logic_error("JsonWriter: document still has an open object or array");
  return out_ + "\n";
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
    file << text;
    file.flush();
    file.close();
    if (!file) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + tmp + " (for " + path + ")");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp + " to " + path + ": " + reason);
  }
}

} // namespace capsim
