#include "eval_config.hpp"

#include "sarloc/app/avalanche_yaml.hpp"
#include "sarloc/app/yaml_reader.hpp"

namespace sarloc::eval {
namespace {

using app::YamlReader;

void load(YamlReader root, avalanche::EvaluationSetup& setup) {
  // The estimator's sections mean the same here as in a mission file (avalanche_yaml.hpp).
  app::read_simulation(root.child("simulation"), setup.simulation);
  app::read_sog(root.child("sog"), setup.sog);
  app::read_search(root.child("search"), setup.search);
  {
    auto r = root.child("evaluation");
    auto& c = setup.evaluation;
    r.read("trials", c.trials);
    r.read("seed", c.seed);
    r.read("threads", c.threads);
    r.read("step_budget", c.step_budget);
    r.expect_done();
  }
  root.expect_done();
  setup.validate();
}

}  // namespace

void load_avalanche_config(const std::string& path, avalanche::EvaluationSetup& setup) {
  load(YamlReader::from_file(path), setup);
}

void load_avalanche_config_text(const std::string& text, const std::string& name,
                                avalanche::EvaluationSetup& setup) {
  load(YamlReader::from_string(text, name), setup);
}

}  // namespace sarloc::eval
