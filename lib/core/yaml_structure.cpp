#include "core/yaml_structure.h"

#include <yaml.h>

#include "core/errors.h"

namespace dynslam {
namespace {

/// libyaml's parser over one text, freed however the walk ends.
class YamlEvents {
 public:
  explicit YamlEvents(const std::string& text) {
    yaml_parser_initialize(&parser_);
    yaml_parser_set_input_string(&parser_, reinterpret_cast<const unsigned char*>(text.data()),
                                 text.size());
  }
  ~YamlEvents() {
    if (has_event_) yaml_event_delete(&event_);
    yaml_parser_delete(&parser_);
  }
  YamlEvents(const YamlEvents&) = delete;
  YamlEvents& operator=(const YamlEvents&) = delete;

  /// The next event, or nullptr where the text stops being YAML (problem()).
  const yaml_event_t* next() {
    if (has_event_) yaml_event_delete(&event_);
    has_event_ = yaml_parser_parse(&parser_, &event_) != 0;
    return has_event_ ? &event_ : nullptr;
  }
  std::size_t problemLine() const { return parser_.problem_mark.line + 1; }
  std::string problem() const {
    std::string p = parser_.problem ? parser_.problem : "unreadable text";
    if (parser_.context) p += std::string(" (") + parser_.context + ")";
    return p;
  }

 private:
  yaml_parser_t parser_;
  yaml_event_t event_;
  bool has_event_ = false;
};

/// The anchor an event defines, if any.
const yaml_char_t* anchorOf(const yaml_event_t& e) {
  switch (e.type) {
    case YAML_SCALAR_EVENT: return e.data.scalar.anchor;
    case YAML_SEQUENCE_START_EVENT: return e.data.sequence_start.anchor;
    case YAML_MAPPING_START_EVENT: return e.data.mapping_start.anchor;
    default: return nullptr;
  }
}

}  // namespace

void checkYamlStructure(const std::string& path, const std::string& text) {
  YamlEvents events(text);
  int depth = 0, documents = 0;
  for (;;) {
    const yaml_event_t* e = events.next();
    if (!e) throw InputError(path, events.problemLine(), "not valid YAML: " + events.problem());
    const std::size_t line = e->start_mark.line + 1;
    if (e->type == YAML_STREAM_END_EVENT) return;
    if (e->type == YAML_ALIAS_EVENT || anchorOf(*e))
      throw InputError(path, line,
                       "YAML anchors and aliases (& and *) are not supported: write the values "
                       "out");
    if (e->type == YAML_DOCUMENT_START_EVENT && ++documents > 1)
      throw InputError(path, line, "a second YAML document: a config file is one document");
    if (e->type == YAML_SEQUENCE_START_EVENT || e->type == YAML_MAPPING_START_EVENT) {
      if (++depth > kMaxYamlNesting)
        throw InputError(path, line,
                         "lists or maps nested more than " + std::to_string(kMaxYamlNesting) +
                             " levels deep");
    } else if (e->type == YAML_SEQUENCE_END_EVENT || e->type == YAML_MAPPING_END_EVENT) {
      --depth;
    }
  }
}

}  // namespace dynslam
