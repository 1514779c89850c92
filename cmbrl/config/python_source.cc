#include "cmbrl/config/python_source.h"

#include <cctype>

#include "cmbrl/core/check.h"
#include "cmbrl/env/task_list.h"

namespace cmbrl {
namespace {

// Whether `text` is dotted Python identifiers ("a.b_c.D1").
bool IsDottedName(const std::string& text) {
  bool at_start = true;
  for (const char c : text) {
    if (c == '.') {
      if (at_start) return false;
      at_start = true;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_' ||
               (!at_start && std::isdigit(static_cast<unsigned char>(c)))) {
      at_start = false;
    } else {
      return false;
    }
  }
  return !at_start;
}

void RequireDeclared(const char* key, const std::string& value) {
  if (value.empty()) return;
  const size_t colon = value.find(':');
  Require(colon != std::string::npos && IsDottedName(value.substr(0, colon)) &&
              IsDottedName(value.substr(colon + 1)),
          "{} is '{}': expected 'module:attribute' (e.g. 'my_envs:make_arm'; the module is "
          "imported with the folders of python.path first)",
          key, value);
}

}  // namespace

void ValidatePythonSourceOptions(const PythonSourceOptions& p) {
  RequireDeclared("env", p.env);
  RequireDeclared("reward", p.reward);
  RequireDeclared("termination", p.termination);
  for (const std::string& folder : p.path) {
    Require(!folder.empty(), "path holds an empty folder name");
  }
}

std::string DeclaredEnvName(const std::string& declared) {
  const size_t colon = declared.find(':');
  return declared.substr(0, colon) + "." + declared.substr(colon + 1) + "()";
}

std::string DeclaredEnvTask(const std::string& declared) {
  return kPythonTaskPrefix + DeclaredEnvName(declared);
}

}  // namespace cmbrl
