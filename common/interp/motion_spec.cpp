#include "interp/motion_spec.h"

#include "core/error.h"
#include "spec/spec_object.h"

namespace gp {
namespace {

constexpr long long kMaxSteps = 1000000;

}  // namespace

MotionSpec parse_motion_spec(const Json& j, const std::string& file, const PoseSet& poses) {
  check_schema(j, "motion", {1}, file);
  SpecObject root(j, file);
  root.allow("schema");
  MotionSpec spec;
  spec.default_steps =
      static_cast<int>(root.integer("steps", spec.default_steps, Range::between(1, kMaxSteps)));
  const SpecArray sequence = root.array("sequence");
  if (sequence.empty()) throw SpecError("sequence has no poses", root.where("sequence"));
  for (size_t i = 0; i < sequence.size(); ++i) {
    MotionKey key;
    const Json& item = sequence.at(i);
    if (item.is_string()) {
      key.pose = item.get<std::string>();
      key.pose_index = poses.index_of(key.pose, sequence.where(i));
      key.steps = i == 0 ? 0 : spec.default_steps;
    } else if (item.is_object()) {
      const SpecObject o = sequence.object(i);
      key.pose = o.required_string("pose");
      key.pose_index = poses.index_of(key.pose, o.where("pose"));
      if (i == 0 && o.has("steps"))
        throw SpecError("the first pose has no transition leading to it; put steps on later poses",
                        o.where("steps"));
      key.steps = i == 0 ? 0
                         : static_cast<int>(o.integer("steps", spec.default_steps,
                                                      Range::between(1, kMaxSteps)));
      o.finish();
    } else {
      throw SpecError("expected a pose name or an object {\"pose\", \"steps\"}, found " +
                          json_type_name(item),
                      sequence.where(i));
    }
    spec.keys.push_back(key);
  }
  if (auto anchor = root.optional_object("anchor")) {
    if (anchor->has("vertex_ids") && anchor->has("fraction"))
      throw SpecError("give either vertex_ids or fraction, not both", anchor->where("fraction"));
    if (anchor->has("vertex_ids")) {
      const long long nv = poses.V.empty() ? 0 : static_cast<long long>(poses.V[0].rows());
      const std::vector<double> ids =
          anchor->numbers("vertex_ids", std::nullopt, Range::between(0, static_cast<double>(nv - 1)));
      if (ids.empty()) throw SpecError("no anchor vertices", anchor->where("vertex_ids"));
      for (size_t i = 0; i < ids.size(); ++i) {
        if (ids[i] != static_cast<double>(static_cast<long long>(ids[i])))
          throw SpecError("expected an integer vertex id", anchor->where("vertex_ids/" + std::to_string(i)));
        spec.anchor.vertex_ids.push_back(static_cast<int>(ids[i]));
      }
    }
    spec.anchor.fraction = anchor->number("fraction", spec.anchor.fraction, Range::between(1e-9, 1.0));
    anchor->finish();
  }
  root.finish();
  return spec;
}

MotionSpec read_motion_spec(const std::filesystem::path& path, const PoseSet& poses) {
  return parse_motion_spec(read_json_file(path), path.string(), poses);
}

std::vector<MotionFrame> motion_frames(const MotionSpec& spec) {
  std::vector<MotionFrame> frames;
  if (spec.keys.empty()) return frames;
  MotionFrame first;
  first.from = first.to = spec.keys[0].pose_index;
  first.key = 0;
  frames.push_back(first);
  for (size_t k = 1; k < spec.keys.size(); ++k) {
    const int n = spec.keys[k].steps;
    for (int j = 1; j <= n; ++j) {
      MotionFrame fr;
      fr.index = static_cast<int>(frames.size());
      fr.from = spec.keys[k - 1].pose_index;
      fr.to = spec.keys[k].pose_index;
      fr.t = j == n ? 1.0 : static_cast<double>(j) / static_cast<double>(n);
      fr.transition = static_cast<int>(k - 1);
      fr.key = j == n ? static_cast<int>(k) : -1;
      frames.push_back(fr);
    }
  }
  return frames;
}

OrderedJson to_json(const MotionSpec& spec) {
  OrderedJson j;
  j["schema"] = schema_tag("motion", 1);
  j["steps"] = spec.default_steps;
  OrderedJson seq = OrderedJson::array();
  for (size_t i = 0; i < spec.keys.size(); ++i) {
    OrderedJson k;
    k["pose"] = spec.keys[i].pose;
    if (i > 0) k["steps"] = spec.keys[i].steps;
    seq.push_back(k);
  }
  j["sequence"] = seq;
  OrderedJson anchor;
  if (!spec.anchor.vertex_ids.empty())
    anchor["vertex_ids"] = spec.anchor.vertex_ids;
  else
    anchor["fraction"] = spec.anchor.fraction;
  j["anchor"] = anchor;
  return j;
}

}  // namespace gp
