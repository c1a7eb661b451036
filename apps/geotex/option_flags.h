#pragma once
// Command-line flags made from option tables (geotex/core/options.h): one flag per option, named,
// documented, defaulted and range-checked by the table alone.
//
// A command adds the tables of its options structs to a FlagSet, each under an owner (the command, or
// each method of `denoise`); after parsing, resolve() builds an options struct from the defaults, the
// chosen preset and the flags given, and refuses a flag that belongs to another owner, before any work:
//
//   auto flags = std::make_shared<FlagSet>(app);
//   flags->add("smooth", SmoothingOptions::table());
//   app.callback([=] { SmoothingOptions o = flags->resolve<SmoothingOptions>("smooth"); … });

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "geotex/core/options.h"

namespace geotex::cli {

class FlagSet {
 public:
  explicit FlagSet(CLI::App& app);
  ~FlagSet();

  //! Every option of every command as JSON: {command: {owner: {option: {flag, kind, default, lo, hi,
  //! choices, automatic}}}}, a subcommand named with its command ("texture extract"); the hidden
  //! `geotex options` prints it, and a test compares it with Python.
  static nlohmann::json describe_all();

  //! Add a flag for every option of \p table (and a --preset flag when it has presets), owned by \p owner.
  //! Options of the same name from several owners share one flag; its help lists each owner's default.
  //! \param defaults the values shown as defaults (the struct's initializers unless given).
  template <class O>
  void add(const std::string& owner, const OptionTable<O>& table, const std::string& group = "", const O& defaults = O{}) {
    for (const auto& f : table.fields()) add_flag(owner, f.info, format_option_value(f.get(defaults)), group);
    for (const auto& p : table.presets()) add_preset(owner, p.name, p.help);
  }

  //! The options of \p owner: \p start (the defaults), then the preset given with --preset, then every
  //! flag given. \throw InvalidOption for a flag of another owner, an unknown preset or a bad value.
  template <class O>
  O resolve(const std::string& owner, const OptionTable<O>& table, O start = O{}) const {
    check_owner(owner);
    if (!preset_.empty()) table.apply_preset(start, preset_);
    for (const auto& [name, flag] : flags_)
      if (flag.given() && flag.owners.count(owner))
        table.set(start, name, parse_option_value(flag.by_owner.at(owner), flag.value));
    table.check(start);
    return start;
  }
  template <class O>
  O resolve(const std::string& owner) const {
    return resolve<O>(owner, O::table());
  }

  //! Whether option \p name was given on the command line.
  bool given(const std::string& name) const;
  CLI::App& app() { return app_; }
  //! The preset given with --preset ("" if none).
  const std::string& preset() const { return preset_; }
  //! Refuse every flag given that \p owner does not have. \throw InvalidOption.
  void check_owner(const std::string& owner) const;

 private:
  struct Flag {
    OptionInfo info;                            // the first owner's (name, kind and help)
    std::map<std::string, OptionInfo> by_owner;  // each owner's own bounds and choices
    std::set<std::string> owners;
    std::vector<std::pair<std::string, std::string>> defaults;  // (owner, default) for the help
    std::string value;
    CLI::Option* option = nullptr;      // the flag itself
    std::vector<CLI::Option*> extra;    // hidden spellings: --no-NAME, value aliases
    bool given() const;
  };
  void add_flag(const std::string& owner, const OptionInfo& info, const std::string& def, const std::string& group);
  void add_preset(const std::string& owner, const std::string& name, const std::string& help);
  void describe(Flag& flag) const;
  size_t owners_count() const { return all_owners_.size(); }

  CLI::App& app_;
  std::map<std::string, Flag> flags_;
  std::string preset_;
  CLI::Option* preset_option_ = nullptr;
  std::set<std::string> all_owners_;
  std::map<std::string, std::set<std::string>> presets_;  // preset → owners
  std::vector<std::pair<std::string, std::string>> preset_help_;
};

//! The options of \p o as a JSON object (for reports): {"alpha": 0.1, "potential": "quadratic", …}.
template <class O>
nlohmann::json options_json(const O& o, const OptionTable<O>& table = O::table()) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, v] : table.values(o)) {
    if (std::holds_alternative<std::monostate>(v)) j[name] = "auto";
    else if (const auto* b = std::get_if<bool>(&v)) j[name] = *b;
    else if (const auto* i = std::get_if<int64_t>(&v)) j[name] = *i;
    else if (const auto* d = std::get_if<double>(&v)) j[name] = *d;
    else if (const auto* s = std::get_if<std::string>(&v)) j[name] = *s;
    else if (const auto* p = std::get_if<Vec3>(&v)) j[name] = {(*p)[0], (*p)[1], (*p)[2]};
  }
  return j;
}

}  // namespace geotex::cli
