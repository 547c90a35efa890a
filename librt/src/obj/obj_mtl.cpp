#include "obj/obj_mtl.h"

#include "obj/obj_scan.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <optional>

namespace librt::detail {

namespace {

/// The text without leading and trailing spaces and tabs.
std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

/// The next space- or tab-separated token of `rest`, removed from it; "" at the end.
std::string_view next_token(std::string_view& rest) {
    rest = trim(rest);
    std::size_t end = 0;
    while (end < rest.size() && rest[end] != ' ' && rest[end] != '\t') ++end;
    const std::string_view token = rest.substr(0, end);
    rest.remove_prefix(end);
    return token;
}

/// 'text', built by appending (GCC 12 warns falsely, -Wrestrict, on "literal" + string).
std::string quoted(std::string_view text) {
    std::string out(1, '\'');
    out += text;
    out += '\'';
    return out;
}

/// A float for a message: shortest round-trip form.
std::string number_text(float x) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
    return std::string(buffer, result.ptr);
}

class MtlParser {
public:
    MtlParser(const std::string& name, std::vector<MeshMaterial>& materials,
              std::vector<std::string>& warnings)
        : name_(name), materials_(materials), warnings_(warnings) {}

    void line(std::string_view text, std::size_t number);
    void finish() { flush(); }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(name_ + ":" + std::to_string(line_) + ": " + what);
    }
    void warn(const std::string& what) {
        warnings_.push_back(name_ + ":" + std::to_string(line_) + ": material " +
                            quote_untrusted(current_.name) + ": " + what);
    }
    /// Between lo and hi numbers (no trailing comment counted), each strictly parsed.
    std::vector<float> numbers(std::string_view keyword, std::string_view rest, std::size_t lo,
                               std::size_t hi);
    std::optional<glm::vec3> colour(std::string_view keyword, std::string_view rest);
    void flush();

    const std::string& name_;
    std::vector<MeshMaterial>& materials_;
    std::vector<std::string>& warnings_;
    std::size_t line_ = 0;
    bool open_ = false;  // a newmtl was seen
    MeshMaterial current_;
    std::size_t current_line_ = 0;  // its newmtl line
    bool has_kd_ = false, has_d_ = false;
};

std::vector<float> MtlParser::numbers(std::string_view keyword, std::string_view rest,
                                      std::size_t lo, std::size_t hi) {
    std::vector<float> out;
    for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        if (t.front() == '#') break;  // a trailing comment
        float value = 0.0f;
        switch (parse_float(t, value)) {
            case NumberStatus::Ok:
                break;
            case NumberStatus::TooLarge:
                fail(quoted(keyword) + " number " + std::string(t.substr(0, 40)) +
                     " is not finite in single precision");
            case NumberStatus::Malformed:
                fail(quoted(keyword) + " has a malformed number " + quoted(t.substr(0, 40)));
        }
        out.push_back(value);
    }
    if (out.size() < lo || out.size() > hi) {
        const std::string range =
            lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
        fail(quoted(keyword) + " needs " + range + " numbers, found " + std::to_string(out.size()));
    }
    return out;
}

std::optional<glm::vec3> MtlParser::colour(std::string_view keyword, std::string_view rest) {
    const std::string_view first = trim(rest).substr(0, trim(rest).find_first_of(" \t"));
    if (first == "spectral" || first == "xyz") {
        std::string statement(keyword);
        statement += ' ';
        statement += first;
        warn(quoted(statement) + " is not supported: the value is ignored");
        return std::nullopt;
    }
    const std::vector<float> v = numbers(keyword, rest, 1, 3);
    if (v.size() == 2) fail(quoted(keyword) + " needs 1 or 3 numbers, found 2");
    // One number r means (r, r, r) (MTL specification).
    return v.size() == 1 ? glm::vec3(v[0]) : glm::vec3(v[0], v[1], v[2]);
}

void MtlParser::flush() {
    if (!open_) return;
    open_ = false;
    const std::size_t saved = line_;
    line_ = current_line_;
    if (current_.name.empty()) {
        warnings_.push_back(name_ + ":" + std::to_string(line_) +
                            ": newmtl without a name: material ignored");
        line_ = saved;
        return;
    }
    // The dielectric the renderer makes of illum 4, 6, 7 or d < 1 needs an index > 0.
    const bool dielectric = current_.illum == 4 || current_.illum == 6 || current_.illum == 7 ||
                            current_.dissolve < 1.0f;
    if (dielectric && !(current_.ior > 0.0f)) {
        warn(std::string("Ni ") + number_text(current_.ior) +
             " is not a valid index of refraction for a transparent material (must be > 0): "
             "using 1.5");
        current_.ior = 1.5f;
    }
    materials_.push_back(current_);
    line_ = saved;
}

void MtlParser::line(std::string_view text, std::size_t number) {
    line_ = number;
    std::string_view rest = text;
    const std::string_view keyword = next_token(rest);
    if (keyword.empty() || keyword.front() == '#') return;
    if (keyword == "newmtl") {
        flush();
        // tinyobjloader's defaults, which librt always had: black, opaque, illum 0.
        current_ = MeshMaterial{};
        current_.diffuse = glm::vec3(0.0f);
        current_.illum = 0;
        current_.name = std::string(trim(rest));
        current_.defined_at = name_ + ":" + std::to_string(number);
        current_line_ = number;
        has_kd_ = has_d_ = false;
        open_ = true;
        return;
    }
    if (!open_) return;  // statements before the first newmtl belong to no material
    auto set_colour = [&](glm::vec3& target) {
        if (const std::optional<glm::vec3> c = colour(keyword, rest)) target = *c;
    };
    if (keyword == "Kd") {
        set_colour(current_.diffuse);
        has_kd_ = true;
    } else if (keyword == "Ks") {
        set_colour(current_.specular);
    } else if (keyword == "Ke") {
        set_colour(current_.emission);
    } else if (keyword == "Ka" || keyword == "Tf") {
        glm::vec3 unused{};
        set_colour(unused);  // checked, not used
    } else if (keyword == "Ni") {
        current_.ior = numbers(keyword, rest, 1, 1)[0];
    } else if (keyword == "Ns" || keyword == "sharpness") {
        (void)numbers(keyword, rest, 1, 1);
    } else if (keyword == "d" || keyword == "Tr") {
        std::string_view values = rest;
        if (keyword == "d" && trim(values).substr(0, 5) == "-halo") {
            values = trim(values).substr(5);
        }
        float value = numbers(keyword, values, 1, 1)[0];
        if (value < 0.0f || value > 1.0f) {
            const float clamped = std::clamp(value, 0.0f, 1.0f);
            std::string message(keyword);
            message += ' ';
            message += number_text(value);
            warn(message + " is outside [0, 1]: using " + number_text(clamped));
            value = clamped;
        }
        // d wins over Tr (Tr is not in the specification; Tr = 1 - d where used).
        if (keyword == "d") {
            current_.dissolve = value;
            has_d_ = true;
        } else if (!has_d_) {
            current_.dissolve = 1.0f - value;
        }
    } else if (keyword == "illum") {
        const float value = numbers(keyword, rest, 1, 1)[0];
        if (value != std::floor(value) || std::fabs(value) > 1e6f) {
            fail(std::string("'illum' needs an integer, found ") + number_text(value));
        }
        current_.illum = static_cast<int>(value);  // |value| <= 1e6: in range
    } else if (keyword == "map_Kd") {
        // Options come first, each a '-name' with a fixed count of arguments (up to three
        // numbers for -o, -s, -t); the rest of the line is the path.
        for (;;) {
            std::string_view probe = rest;
            const std::string_view option = next_token(probe);
            if (option.size() < 2 || option.front() != '-') break;
            rest = probe;
            if (option == "-o" || option == "-s" || option == "-t") {
                for (int k = 0; k < 3; ++k) {
                    std::string_view look = rest;
                    float ignored = 0.0f;
                    if (parse_float(next_token(look), ignored) != NumberStatus::Ok) break;
                    rest = look;
                }
            } else if (option == "-mm") {
                (void)next_token(rest);
                (void)next_token(rest);
            } else {
                (void)next_token(rest);  // -blendu on, -bm 1, -imfchan l, -texres 512...
            }
        }
        const std::string path = normalise_separators(trim(rest));
        if (path.empty()) {
            warn("map_Kd without a file name: ignored");
            return;
        }
        current_.diffuse_texture = path;
        // A texture without Kd: tinyobjloader's (and so librt's) default of 0.6.
        if (!has_kd_) current_.diffuse = glm::vec3(0.6f);
    }
    // Anything else (maps other than map_Kd, PBR extensions) does not change librt's
    // materials and is ignored.
}

}  // namespace

std::string normalise_separators(std::string_view path) {
    std::string out(path);
    std::replace(out.begin(), out.end(), '\\', '/');
    return out;
}

void parse_mtl(std::string_view text, const std::string& name, std::vector<MeshMaterial>& materials,
               std::vector<std::string>& warnings) {
    if (text.find('\0') != std::string_view::npos) {
        throw Error(name + ": NUL byte: not an MTL text file");
    }
    MtlParser parser(name, materials, warnings);
    std::size_t number = 0, start = 0;
    if (text.substr(0, 3) == "\xef\xbb\xbf") start = 3;  // UTF-8 byte order mark
    // Lines end at \n, \r or \r\n.
    while (start < text.size()) {
        std::size_t end = start;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        parser.line(text.substr(start, end - start), ++number);
        if (end < text.size() && text[end] == '\r' && end + 1 < text.size() &&
            text[end + 1] == '\n')
            ++end;
        start = end + 1;
    }
    parser.finish();
}

}  // namespace librt::detail
