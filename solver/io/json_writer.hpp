#pragma once
// A minimal JSON writer for summary.json and benchmark results (no external library):
// builds a pretty-printed string (2-space indentation) call by call. Doubles print with
// the shortest text that reads back bit-exactly; NaN and infinities, which JSON lacks,
// become null. Misuse (a value in an object without a key, unbalanced ends) throws
// std::logic_error.
#include "common/vec3.hpp"

#include <string>
#include <type_traits>
#include <vector>

namespace capsim {

class JsonWriter {
public:
  // Containers: the key-less forms are for the top level and for array elements.
  void begin_object();
  void begin_object(const std::string& key);
  void end_object();
  void begin_array();
  void begin_array(const std::string& key);
  void end_array();

  // Names the next value, inside an object.
  void key(const std::string& name);

  void value(double v);
  void value(bool v);
  void value(const std::string& v);
  void value(const char* v); // else a string literal would pick value(bool)
  template <
      class Int,
      std::enable_if_t<std::is_integral_v<Int> && !std::is_same_v<Int, bool>, int> = 0>
  void value(Int v) {
    raw(std::to_string(v));
  }
  void null();

  template <class T> void field(const std::string& name, const T& v) {
    key(name);
    value(v);
  }
  void field(const std::string& name, const std::vector<double>& v); // one line
  void matrix(const std::string& name, const Mat3& m); // [[..], [..], [..]], one line

  // The finished document, ending in a newline; throws if a container is still open.
  std::string str() const;

private:
  struct Level {
    bool is_object;
    int count;
  };
  void before_value();
  void raw(const std::string& text);
  void close(bool is_object);
  void newline();

  std::string out_;
  std::vector<Level> stack_;
  bool have_key_ = false;
};

// "text" with JSON escapes.
std::string json_quote(const std::string& text);

// A number as JSON: %.17g, or null for NaN and infinities.
std::string json_number(double v);

// Writes path.tmp, closes it, then renames it over `path`, so readers never see a partly
// written file. Throws std::runtime_error naming the path on failure.
void write_text_atomically(const std::string& path, const std::string& text);

} // namespace capsim
