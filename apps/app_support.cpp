#include "app_support.hpp"

#include <fstream>
#include <iostream>
#include <sstream>

#include "epuck2/logs/log.hpp"
#include "epuck2/logs/output.hpp"

namespace epuck2::app {

void write_json(const nlohmann::json& j, const std::string& path) {
  const std::string text = j.dump(2) + "\n";
  if (path == "-") {
    std::cout << text;
    return;
  }
  logs::write_file_atomically(path, text);
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw logs::InputError(path, 0, 0, "cannot open the file for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // Turn the byte offset into line and column.
    int line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw logs::InputError(path, line, col, std::string("invalid JSON: ") + e.what());
  }
}

}  // namespace epuck2::app
