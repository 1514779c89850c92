#include "cmbrl/run/learner_state.h"

#include <fstream>
#include <stdexcept>
#include <string>

#include "cmbrl/core/check.h"
#include "cmbrl/core/files.h"

namespace cmbrl {

void WriteLearnerState(const std::filesystem::path& path, const nlohmann::json& state) {
  WriteFile(path, state.dump(2));
}

void ReadLearnerState(const std::filesystem::path& path,
                      const std::function<void(const nlohmann::json&)>& read) {
  try {
    std::ifstream in(path);
    Require(static_cast<bool>(in), "cannot read it");
    read(nlohmann::json::parse(in));
  } catch (const nlohmann::json::exception& error) {
    Fail("'{}' is damaged: {}", path.string(), error.what());
  } catch (const std::invalid_argument&) {
    Fail("'{}' is damaged: a figure is not a number", path.string());
  } catch (const std::out_of_range&) {
    Fail("'{}' is damaged: a figure is out of range", path.string());
  } catch (const Error& error) {
    Fail("'{}' is damaged: {}", path.string(), error.what());
  }
}

double StateNumber(const nlohmann::json& state, const char* key) {
  return std::stod(state.at(key).get<std::string>());
}

}  // namespace cmbrl
