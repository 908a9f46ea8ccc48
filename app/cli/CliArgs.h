#pragma once
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hvx::app {

/// Minimal command-line parsing for holovox-cli subcommands: positional arguments plus
/// `--name value` and `--flag` options, checked against the options a command declares.
class CliArgs {
public:
    /// Parses argv[first..]; `valued` take a value, `flags` do not. Throws core::Error on an
    /// unknown option or a missing value.
    CliArgs(int argc, char** argv, int first, const std::vector<std::string>& valued,
            const std::vector<std::string>& flags);
    const std::vector<std::string>& positional() const { return positional_; }
    std::optional<std::string> value(const std::string& name) const;
    bool flag(const std::string& name) const { return flags_.count(name) != 0; }
    /// Integer option in [lo, hi], or `fallback` when absent; throws core::Error otherwise.
    long integer(const std::string& name, long fallback, long lo, long hi) const;
    /// Floating-point option; throws core::Error when not a number.
    std::optional<double> number(const std::string& name) const;
    /// `count` comma-separated finite numbers ("X,Y,Z"); throws core::Error naming `what` otherwise.
    static std::vector<double> numbers(const std::string& text, std::size_t count, const std::string& what);
    /// Comma-separated "A:B" pairs of finite numbers ("0:0,50:1"); throws core::Error naming
    /// `what`, the pair's parts (`pair`, e.g. "GRADIENT:SCALE") and `example` otherwise.
    static std::vector<std::pair<double, double>> pairs(const std::string& text, const std::string& what,
                                                        const std::string& pair, const std::string& example);

private:
    std::vector<std::string> positional_;
    std::map<std::string, std::string> values_;
    std::map<std::string, bool> flags_;
};

}  // namespace hvx::app
