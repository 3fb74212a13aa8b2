#include "bushel/scenario/yaml_structure.hpp"

#include <map>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include "bushel/core/input_error.hpp"

namespace bushel {
namespace {

int line_of(const YAML::Mark& mark) { return mark.is_null() ? 0 : mark.line + 1; }

// Walks the parser's events with a stack of the open lists and maps.
class StructureCheck : public YAML::EventHandler {
 public:
  explicit StructureCheck(const std::string& source) : source_(source) {}

  void OnDocumentStart(const YAML::Mark& mark) override {
    if (++documents_ > 1) {
      fail(line_of(mark),
           "a second YAML document (after a '---' line): a scenario file holds one, and bushel would ignore the rest");
    }
  }
  void OnDocumentEnd() override {}

  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor, "~", 1); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string& value) override {
    leaf(mark, anchor, value, 1);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    const auto it = sizes_.find(anchor);
    if (it == sizes_.end()) {
      fail(line_of(mark), "an alias (*name) to the list or map that contains it: the tree would never end");
    }
    if (expecting_key()) fail(line_of(mark), "an alias (*name) as a key: keys are plain names");
    leaf(mark, 0, "", it->second);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    open(mark, anchor, false);
  }
  void OnSequenceEnd() override { close(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    open(mark, anchor, true);
  }
  void OnMapEnd() override { close(); }

 private:
  struct Open {
    bool map = false;
    bool key_next = true;             // (a map) the next node is a key
    YAML::anchor_t anchor = 0;        // its own anchor, if any
    std::size_t values = 1;           // values inside it, aliases expanded, itself included
    std::map<std::string, int> keys;  // (a map) key -> line
  };

  [[noreturn]] void fail(int line, const std::string& problem) const { throw InputError(problem).at(source_, line); }

  bool expecting_key() const { return !stack_.empty() && stack_.back().map && stack_.back().key_next; }

  void open(const YAML::Mark& mark, YAML::anchor_t anchor, bool map) {
    if (expecting_key()) {
      fail(line_of(mark),
           fmt::format("a {} as a key (a complex key, '? ...'): keys are plain names", map ? "map" : "list"));
    }
    count(1);
    stack_.push_back({map, true, anchor, 1, {}});
  }

  void close() {
    const Open done = std::move(stack_.back());
    stack_.pop_back();
    if (done.anchor != 0) sizes_[done.anchor] = done.values;
    add_to_parent(done.values);
  }

  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor, const std::string& text, std::size_t values) {
    if (expecting_key()) {
      const int line = line_of(mark);
      const auto [it, fresh] = stack_.back().keys.emplace(text, line);
      if (!fresh) {
        fail(line, fmt::format("the key '{}' appears twice in one map (lines {} and {}); give it once", text,
                               it->second, line));
      }
    }
    if (anchor != 0) sizes_[anchor] = values;
    count(values);
    add_to_parent(values);
  }

  // Counts values into the whole document's.
  void count(std::size_t values) {
    total_ += values;
    if (total_ > max_yaml_values) {
      fail(0, fmt::format("more than {} values once its aliases (*name) are expanded", max_yaml_values));
    }
  }

  // Counts a finished node's values into the container that holds it and ends a map's key or
  // value.
  void add_to_parent(std::size_t values) {
    if (stack_.empty()) return;
    Open& top = stack_.back();
    top.values += values;
    if (top.map) top.key_next = !top.key_next;
  }

  const std::string& source_;
  std::vector<Open> stack_;
  std::map<YAML::anchor_t, std::size_t> sizes_;  // finished anchors -> their values
  std::size_t total_ = 0;
  int documents_ = 0;
};

}  // namespace

void check_yaml_structure(std::string_view text, const std::string& source) {
  std::istringstream in{std::string(text)};
  StructureCheck check(source);
  try {
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(check)) {
    }
  } catch (const YAML::Exception& e) {
    throw InputError("not valid YAML: " + e.msg).at(source, e.mark.is_null() ? 0 : e.mark.line + 1);
  }
}

}  // namespace bushel
