#pragma once
// The named values of a key that takes one of a few names (time.scheme, backend,
// membrane.load, ...): one table per key gives both the parsing and the printing, and an
// unknown name gets the same message everywhere, naming the key and the allowed names.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace capsim {

template <class E> using Choice = std::pair<const char*, E>;

// "a, b, c": the names of `choices`, for messages.
template <class E, std::size_t N> std::string choice_list(const Choice<E> (&choices)[N]) {
  std::string names;
  for (const Choice<E>& c : choices)
    names += (names.empty() ? "" : ", ") + std::string(c.first);
  return names;
}

// The value called `name` in `choices`; throws std::invalid_argument("<key> must be one
// of {a, b}, got '<name>'") for any other name.
template <class E, std::size_t N>
E parse_choice(const char* key, const std::string& name, const Choice<E> (&choices)[N]) {
  for (const Choice<E>& c : choices)
    if (name == c.first)
      return c.second;
  throw std::invalid_argument(std::string(key) + " must be one of {" +
                              choice_list(choices) + "}, got '" + name + "'");
}

// The name of `value` in `choices`.
template <class E, std::size_t N>
std::string choice_name(E value, const Choice<E> (&choices)[N]) {
  for (const Choice<E>& c : choices)
    if (c.second == value)
      return c.first;
  throw std::logic_error("a value without a name"); // every table names all its values
}

} // namespace capsim
