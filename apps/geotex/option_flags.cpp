#include "option_flags.h"

#include <fmt/format.h>

namespace geotex::cli {

namespace {

std::vector<const FlagSet*>& registry() {
  static std::vector<const FlagSet*> r;
  return r;
}

// "texture extract" for a subcommand of a command, "smooth" for a command.
std::string command_name(const CLI::App& app) {
  std::string name = app.get_name();
  for (const CLI::App* p = app.get_parent(); p && p->get_parent(); p = p->get_parent()) name = p->get_name() + " " + name;
  return name;
}

const char* type_name(const OptionInfo& info) {
  switch (info.kind) {
    case OptionKind::Bool: return "";
    case OptionKind::Int: return info.automatic ? "INT|auto" : "INT";
    case OptionKind::Real: return info.automatic ? "FLOAT|auto" : "FLOAT";
    case OptionKind::Text: return "TEXT";
    case OptionKind::Choice: return "NAME";
    case OptionKind::Vec3: return "X,Y,Z";
  }
  return "";
}

}  // namespace

FlagSet::FlagSet(CLI::App& app) : app_(app) { registry().push_back(this); }

FlagSet::~FlagSet() { std::erase(registry(), this); }

nlohmann::json FlagSet::describe_all() {
  static const char* kinds[] = {"bool", "int", "float", "str", "choice", "vec3"};
  nlohmann::json all = nlohmann::json::object();
  for (const FlagSet* set : registry())
    for (const auto& [name, flag] : set->flags_)
      for (const auto& [owner, def] : flag.defaults) {
        const OptionInfo& info = flag.by_owner.at(owner);
        nlohmann::json& j = all[command_name(set->app_)][owner][name];
        j["flag"] = info.cli_flag();
        j["kind"] = kinds[static_cast<int>(info.kind)];
        j["default"] = def;
        j["lo"] = info.bounds.lo;
        j["hi"] = info.bounds.hi;
        j["choices"] = info.choices;
        j["automatic"] = info.automatic;
      }
  return all;
}

void FlagSet::describe(Flag& flag) const {
  const OptionInfo& info = flag.info;
  std::string text = info.help;
  if (info.kind == OptionKind::Choice) {
    std::set<std::vector<std::string>> distinct;
    for (const auto& [o, i] : flag.by_owner) distinct.insert(i.choices);
    if (distinct.size() <= 1) {
      text += fmt::format(" ({})", fmt::join(info.choices, "|"));
    } else {
      std::vector<std::string> parts;
      for (const auto& [o, i] : flag.by_owner) parts.push_back(fmt::format("{}: {}", o, fmt::join(i.choices, "|")));
      text += fmt::format(" ({})", fmt::join(parts, "; "));
    }
  }
  if (info.kind == OptionKind::Int || info.kind == OptionKind::Real || info.kind == OptionKind::Vec3) {
    Bounds shown = info.bounds;  // the limits of the field's type are not worth showing
    if (shown.hi >= 2147483647.0) shown.hi = std::numeric_limits<double>::infinity();
    if (shown.lo <= -2147483648.0) shown.lo = -std::numeric_limits<double>::infinity();
    if (std::isfinite(shown.lo) || std::isfinite(shown.hi)) text += fmt::format(" ({})", shown.describe());
  }
  if (info.kind == OptionKind::Bool) {
    std::vector<std::string> spellings{"--no-" + info.cli_flag().substr(2)};
    for (const auto& [alias, v] : info.aliases) spellings.push_back(cli_flag(alias) + (v.empty() || v == "true" ? "" : " (" + v + ")"));
    text += fmt::format(" (also {})", fmt::join(spellings, ", "));
  }
  if (!info.ref.empty()) text += fmt::format(" [{}]", info.ref);
  // Defaults: one value, or one per owner when they differ.
  std::set<std::string> distinct;
  for (const auto& [o, d] : flag.defaults) distinct.insert(d);
  if (distinct.size() == 1) {
    text += fmt::format("; default {}", *distinct.begin());
  } else {
    std::vector<std::string> parts;
    for (const auto& [o, d] : flag.defaults) parts.push_back(o + " " + d);
    text += fmt::format("; default {}", fmt::join(parts, ", "));
  }
  if (flag.owners.size() < owners_count()) text += fmt::format(" (only {})", fmt::join(flag.owners, ", "));
  flag.option->description(text);
}

void FlagSet::add_flag(const std::string& owner, const OptionInfo& info, const std::string& def, const std::string& group) {
  auto it = flags_.find(info.name);
  if (it == flags_.end()) {
    Flag& flag = flags_[info.name];
    flag.info = info;
    if (info.kind == OptionKind::Bool) {
      // --name (true), --name=false; hidden spellings: --no-name and value aliases (e.g. --explicit).
      flag.option = app_.add_flag(info.cli_flag(), flag.value, "");
      flag.extra.push_back(app_.add_flag("--no-" + info.cli_flag().substr(2) + "{false}", flag.value, "")->group(""));
      for (const auto& [alias, v] : info.aliases)
        flag.extra.push_back(app_.add_flag(cli_flag(alias) + (v.empty() ? "" : "{" + v + "}"), flag.value, "")->group(""));
    } else {
      std::string names = info.cli_flag();
      for (const auto& [alias, v] : info.aliases)
        if (v.empty()) names += "," + cli_flag(alias);
      flag.option = app_.add_option(names, flag.value, "")->type_name(type_name(info));
      for (const auto& [alias, v] : info.aliases)
        if (!v.empty()) flag.extra.push_back(app_.add_flag(cli_flag(alias) + "{" + v + "}", flag.value, "")->group(""));
    }
    if (!group.empty()) flag.option->group(group);
    it = flags_.find(info.name);
  } else if (it->second.info.kind != info.kind) {
    throw std::logic_error(fmt::format("option {} has two kinds", info.name));
  }
  it->second.owners.insert(owner);
  it->second.by_owner[owner] = info;
  it->second.defaults.emplace_back(owner, def);
  all_owners_.insert(owner);
  for (auto& [n, f] : flags_) describe(f);
}

void FlagSet::add_preset(const std::string& owner, const std::string& name, const std::string& help) {
  if (!preset_option_) {
    preset_option_ = app_.add_option("--preset", preset_, "");
    preset_option_->type_name("NAME");
  }
  presets_[name].insert(owner);
  preset_help_.emplace_back(owner, fmt::format("{}: {}", name, help));
  std::vector<std::string> lines;
  for (const auto& [o, h] : preset_help_) lines.push_back(all_owners_.size() > 1 ? o + " " + h : h);
  preset_option_->description("settings other than the defaults:\n  " + fmt::format("{}", fmt::join(lines, "\n  ")));
}

bool FlagSet::Flag::given() const {
  if (option && option->count() > 0) return true;
  for (const CLI::Option* o : extra)
    if (o->count() > 0) return true;
  return false;
}

bool FlagSet::given(const std::string& name) const {
  auto it = flags_.find(name);
  return it != flags_.end() && it->second.given();
}

void FlagSet::check_owner(const std::string& owner) const {
  for (const auto& [name, flag] : flags_)
    if (flag.given() && !flag.owners.count(owner))
      throw InvalidOption(fmt::format("{} is an option of {}, not of {}", flag.info.cli_flag(),
                                      fmt::join(flag.owners, ", "), owner));
  if (!preset_.empty() && !presets_.count(preset_)) {
    std::set<std::string> names;
    for (const auto& [p, o] : presets_)
      if (o.count(owner)) names.insert(p);
    throw InvalidOption(fmt::format("unknown preset '{}' for {} ({})", preset_, owner,
                                    names.empty() ? "it has none" : fmt::format("{}", fmt::join(names, ", "))));
  }
  if (!preset_.empty() && !presets_.at(preset_).count(owner))
    throw InvalidOption(fmt::format("--preset {} is a preset of {}, not of {}", preset_,
                                    fmt::join(presets_.at(preset_), ", "), owner));
}

}  // namespace geotex::cli
