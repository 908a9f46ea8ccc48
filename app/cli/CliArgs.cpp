#include "app/cli/CliArgs.h"

#include <cstdio>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/base/Error.h"

namespace hvx::app {

CliArgs::CliArgs(int argc, char** argv, int first, const std::vector<std::string>& valued,
                 const std::vector<std::string>& flags) {
    for (int i = first; i < argc; ++i) {
        std::string a = argv[i];
        const bool shortOption = a.size() == 2 && a[0] == '-' && std::isalpha(static_cast<unsigned char>(a[1]));
        if (!shortOption && (a.rfind("--", 0) != 0 || a == "--")) {
            positional_.push_back(a);
            continue;
        }
        std::string name = a.substr(shortOption ? 1 : 2), value;
        const auto eq = name.find('=');
        const bool inlineValue = eq != std::string::npos;
        if (inlineValue) {
            value = name.substr(eq + 1);
            name = name.substr(0, eq);
        }
        if (std::find(flags.begin(), flags.end(), name) != flags.end() && !inlineValue) {
            flags_[name] = true;
        } else if (std::find(valued.begin(), valued.end(), name) != valued.end()) {
            if (!inlineValue) {
                if (i + 1 >= argc) throw core::Error("option --" + name + " needs a value");
                value = argv[++i];
            }
            // Given twice, one would be silently dropped: which was meant is not for Holovox to guess
            // (-o and --output are one option).
            const std::string key = name == "output" ? "o" : name;
            if (!values_.emplace(key, value).second)
                throw core::Error("option --" + name + (key == "o" ? " (or -o)" : "") + " is given twice");
        } else {
            throw core::Error("unknown option --" + name);
        }
    }
}

std::optional<std::string> CliArgs::value(const std::string& name) const {
    const auto it = values_.find(name == "output" ? "o" : name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
}

long CliArgs::integer(const std::string& name, long fallback, long lo, long hi) const {
    const auto v = value(name);
    if (!v) return fallback;
    std::size_t used = 0;
    long x = 0;
    try {
        x = std::stol(*v, &used);
    } catch (...) {
        used = 0;
    }
    if (used != v->size() || v->empty()) throw core::Error("--" + name + " must be an integer, got '" + *v + "'");
    if (x < lo || x > hi)
        throw core::Error("--" + name + " must be between " + std::to_string(lo) + " and " + std::to_string(hi));
    return x;
}

std::optional<double> CliArgs::number(const std::string& name) const {
    const auto v = value(name);
    if (!v) return std::nullopt;
    std::size_t used = 0;
    double x = 0;
    try {
        x = std::stod(*v, &used);
    } catch (...) {
        used = 0;
    }
    if (used != v->size() || v->empty() || !std::isfinite(x))
        throw core::Error("--" + name + " must be a number, got '" + *v + "'");
    return x;
}

std::vector<double> CliArgs::numbers(const std::string& text, std::size_t count, const std::string& what) {
    std::vector<double> v;
    std::size_t at = 0;
    while (at <= text.size()) {
        const auto end = std::min(text.find(',', at), text.size());
        const std::string part = text.substr(at, end - at);
        std::size_t used = 0;
        double x = 0;
        try {
            x = std::stod(part, &used);
        } catch (...) {
            used = 0;
        }
        if (part.empty() || used != part.size() || !std::isfinite(x)) break;
        v.push_back(x);
        at = end + 1;
    }
    if (v.size() != count || at <= text.size())
        throw core::Error(what + " '" + text + "' needs " + std::to_string(count) + " comma-separated numbers");
    return v;
}

std::vector<std::pair<double, double>> CliArgs::pairs(const std::string& text, const std::string& what,
                                                     const std::string& pairName, const std::string& example) {
    std::vector<std::pair<double, double>> out;
    std::size_t at = 0;
    while (at <= text.size()) {
        const auto comma = std::min(text.find(',', at), text.size());
        const std::string pair = text.substr(at, comma - at);
        double a = 0, b = 0;
        char colon = 0, extra = 0;
        if (std::sscanf(pair.c_str(), "%lf %c %lf %c", &a, &colon, &b, &extra) != 3 || colon != ':' || !std::isfinite(a) ||
            !std::isfinite(b))
            throw core::Error(what + " takes " + pairName + " pairs separated by commas, e.g. " + example + " (\"" + pair +
                              "\" given)");
        out.emplace_back(a, b);
        at = comma + 1;
    }
    return out;
}

}  // namespace hvx::app
