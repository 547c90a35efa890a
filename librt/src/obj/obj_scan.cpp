#include "obj/obj_scan.h"

#include <librt/core/error.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <system_error>

namespace librt::detail {

namespace {

/// A statement's tokens, split at spaces and tabs (as tinyobjloader splits them).
class Tokens {
public:
    explicit Tokens(std::string_view line) : rest_(line) {}

    /// The next token, or "" at the end of the line.
    std::string_view next() {
        std::size_t i = 0;
        while (i < rest_.size() && (rest_[i] == ' ' || rest_[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < rest_.size() && rest_[j] != ' ' && rest_[j] != '\t') ++j;
        const std::string_view token = rest_.substr(i, j - i);
        rest_.remove_prefix(j);
        return token;
    }

private:
    std::string_view rest_;
};

/// A token for a message: at most 40 bytes, bytes outside printable ASCII as \xNN.
std::string printable(std::string_view token) {
    constexpr std::size_t kMax = 40;
    std::string out;
    for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            constexpr char hex[] = "0123456789abcdef";
            out += "\\x";
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    if (token.size() > kMax) out += "...";
    return out;
}

/// 'text', built by appending (GCC 12 warns falsely, -Wrestrict, on "literal" + string).
std::string quoted(std::string_view text) {
    std::string out(1, '\'');
    out += text;
    out += '\'';
    return out;
}

/// The text without leading and trailing spaces and tabs.
std::string_view trimmed(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

/// "name:line: NUL byte in column C ..." for the first NUL byte of text, if any.
void check_nul(std::string_view text, std::size_t skip, const std::string& name) {
    const std::size_t nul = text.find('\0', skip);
    if (nul == std::string_view::npos) return;
    // Lines end at \n, \r or \r\n, as in scan_obj.
    std::size_t line = 1, line_start = skip;
    for (std::size_t i = skip; i < nul; ++i) {
        if (text[i] == '\n' || (text[i] == '\r' && (i + 1 >= text.size() || text[i + 1] != '\n'))) {
            ++line;
            line_start = i + 1;
        }
    }
    throw Error(name + ":" + std::to_string(line) + ": NUL byte in column " +
                std::to_string(nul - line_start + 1) + " (a binary file, or UTF-16 text?)");
}

/// Statements tinyobjloader reads or that OBJ defines (curves, surfaces, display
/// attributes) and librt ignores without comment.
bool known_keyword(std::string_view k) {
    static constexpr std::string_view known[] = {
        "v",          "vt",        "vn",       "vp",       "f",      "l",      "p",
        "g",          "o",         "s",        "usemtl",   "mtllib", "t",      "vw",
        "cstype",     "deg",       "bmat",     "step",     "curv",   "curv2",  "surf",
        "parm",       "trim",      "hole",     "scrv",     "sp",     "end",    "con",
        "mg",         "bevel",     "c_interp", "d_interp", "lod",    "usemap", "maplib",
        "shadow_obj", "trace_obj", "ctech",    "stech",    "call",   "csh",    "fo",
    };
    for (const std::string_view s : known)
        if (k == s) return true;
    return false;
}

/// The scan's state: element counts so far and what to report.
class Scanner {
public:
    Scanner(const char* base, const std::string& name, const ObjScanOptions& options)
        : base_(base), name_(name), options_(options) {}

    void line(std::string_view text, std::size_t number);
    ObjScanResult finish();

private:
    /// Error "name:line: what".
    [[noreturn]] void fail(std::size_t line, const std::string& what) const {
        throw Error(name_ + ":" + std::to_string(line) + ": " + what);
    }

    void numbers(Tokens& tokens, std::string_view keyword, std::size_t lo, std::size_t hi,
                 std::size_t line);
    void face(Tokens& tokens, std::size_t line);
    /// Which corner of which face a message is about; its text is built only when a
    /// message is (eagerly, per corner, it was a fifth of the bunny's load: callgrind).
    struct CornerPlace {
        std::size_t face;        ///< numbered from 1
        std::string_view token;  ///< the corner as written
        /// "face N, corner '...': ".
        [[nodiscard]] std::string text() const {
            return "face " + std::to_string(face) + ", corner " + quoted(printable(token)) + ": ";
        }
    };
    void corner_field(std::string_view field, const char* what, std::size_t count, bool check,
                      std::size_t line, const CornerPlace& at);

    /// An absolute index beyond the elements read so far: legal only if the file defines
    /// enough of them later, so it is checked at the end.
    struct ForwardReference {
        std::size_t line;
        const char* what;
        std::int64_t index;
        std::string at;  ///< "face N, corner '...': "
    };

    void usemtl(std::string_view name, std::size_t line);

    const char* base_;  // the text's first byte, for offsets
    const std::string& name_;
    ObjScanOptions options_;
    std::size_t positions_ = 0, uvs_ = 0, normals_ = 0;
    std::size_t faces_ = 0;  // faces of 3+ corners, i.e. the faces load_obj numbers
    std::vector<ForwardReference> forward_;
    std::size_t short_faces_ = 0, short_face_line_ = 0;
    std::size_t lines_points_ = 0, lines_points_line_ = 0;
    std::size_t unknown_ = 0, unknown_line_ = 0;
    std::string unknown_keyword_;
    ObjScanResult result_;
};

void Scanner::numbers(Tokens& tokens, std::string_view keyword, std::size_t lo, std::size_t hi,
                      std::size_t line) {
    std::size_t count = 0;
    for (std::string_view t = tokens.next(); !t.empty(); t = tokens.next()) {
        if (t.front() == '#') {  // a trailing comment
            result_.trailing_comments.push_back(static_cast<std::size_t>(t.data() - base_));
            break;
        }
        ++count;
        if (count > hi) continue;  // reported below with the count
        float value = 0.0f;
        switch (parse_float(t, value)) {
            case NumberStatus::Ok:
                break;
            case NumberStatus::TooLarge:
                fail(line, quoted(keyword) + " number " + printable(t) +
                               " is not finite in single precision");
            case NumberStatus::Malformed:
                fail(line, quoted(keyword) + " has a malformed number " + quoted(printable(t)));
        }
    }
    if (count < lo || count > hi) {
        const std::string range =
            lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
        fail(line,
             quoted(keyword) + " needs " + range + " numbers, found " + std::to_string(count));
    }
}

void Scanner::corner_field(std::string_view field, const char* what, std::size_t count, bool check,
                           std::size_t line, const CornerPlace& at) {
    std::string_view digits = field;
    if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);
    std::int64_t index = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), index);
    if (ec == std::errc::result_out_of_range ||
        (ec == std::errc() && (index > std::numeric_limits<std::int32_t>::max() ||
                               index < -std::int64_t{std::numeric_limits<std::int32_t>::max()}))) {
        fail(line, at.text() + what + " index " + printable(field) + " is out of range");
    }
    if (ec != std::errc() || end != digits.data() + digits.size()) {
        fail(line, at.text() + "malformed " + what + " index '" + printable(field) + "'");
    }
    if (index == 0) fail(line, at.text() + what + " index 0 (OBJ indices start at 1)");
    if (!check) return;
    if (index < 0) {
        // Relative: -1 is the latest element defined above this line.
        if (std::int64_t(count) + index < 0) {
            fail(line, at.text() + "relative " + what + " index " + std::to_string(index) +
                           " reaches before the first " + what + " (" + std::to_string(count) +
                           " defined above)");
        }
    } else if (std::uint64_t(index) > count) {
        forward_.push_back({line, what, index, at.text()});
    }
}

void Scanner::face(Tokens& tokens, std::size_t line) {
    // Faces are numbered like load_obj's other messages: from 1, in file order, not
    // counting those of under 3 corners.
    std::size_t corners = 0;
    for (std::string_view t = tokens.next(); !t.empty(); t = tokens.next()) {
        if (t.front() == '#') {  // a trailing comment
            result_.trailing_comments.push_back(static_cast<std::size_t>(t.data() - base_));
            break;
        }
        ++corners;
        const CornerPlace at{faces_ + 1, t};
        // v, v/vt, v//vn or v/vt/vn.
        const std::size_t s1 = t.find('/');
        const std::string_view v = t.substr(0, s1);
        std::string_view vt, vn;
        if (s1 != std::string_view::npos) {
            const std::string_view rest = t.substr(s1 + 1);
            const std::size_t s2 = rest.find('/');
            vt = rest.substr(0, s2);
            if (s2 != std::string_view::npos) {
                vn = rest.substr(s2 + 1);
                if (vn.empty() || vn.find('/') != std::string_view::npos)
                    fail(line, at.text() + "malformed (expected v, v/vt, v//vn or v/vt/vn)");
            } else if (vt.empty()) {
                fail(line, at.text() + "malformed (expected v, v/vt, v//vn or v/vt/vn)");
            }
        }
        corner_field(v, "position", positions_, true, line, at);
        if (!vt.empty())
            corner_field(vt, "texture coordinate", uvs_, options_.check_uv_indices, line, at);
        if (!vn.empty())
            corner_field(vn, "normal", normals_, options_.check_normal_indices, line, at);
    }
    if (corners > 255) {
        fail(line, "face of " + std::to_string(corners) + " corners (at most 255 are supported)");
    }
    if (corners < 3) {
        if (short_faces_++ == 0) short_face_line_ = line;
        return;
    }
    ++faces_;
}

void Scanner::line(std::string_view text, std::size_t number) {
    if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
        fail(number,
             "NUL byte in column " + std::to_string(nul + 1) + " (a binary file, or UTF-16 text?)");
    }
    Tokens tokens(text);
    const std::string_view keyword = tokens.next();
    if (keyword.empty() || keyword.front() == '#') return;
    if (keyword == "v") {
        numbers(tokens, keyword, 3, 7, number);
        ++positions_;
    } else if (keyword == "vt") {
        numbers(tokens, keyword, 1, 3, number);
        ++uvs_;
    } else if (keyword == "vn") {
        numbers(tokens, keyword, 3, 3, number);
        ++normals_;
    } else if (keyword == "f") {
        face(tokens, number);
    } else if (keyword == "usemtl" || keyword == "mtllib") {
        const std::string_view rest = trimmed(
            text.substr(static_cast<std::size_t>(keyword.data() + keyword.size() - text.data())));
        if (keyword == "usemtl") {
            usemtl(rest, number);
        } else {
            result_.mtllibs.emplace_back(std::string(rest), number);
        }
    } else if (keyword == "l" || keyword == "p") {
        if (lines_points_++ == 0) lines_points_line_ = number;
    } else if (!known_keyword(keyword)) {
        if (unknown_++ == 0) {
            unknown_line_ = number;
            unknown_keyword_ = printable(keyword);
        }
    }
}

void Scanner::usemtl(std::string_view name, std::size_t line) {
    auto& names = result_.material_names;
    std::size_t index = 0;
    while (index < names.size() && names[index].first != name) ++index;
    if (index == names.size()) names.emplace_back(std::string(name), line);
    auto& runs = result_.material_runs;
    if (!runs.empty() && runs.back().first_face == faces_) runs.pop_back();  // no faces between
    runs.push_back({faces_, index});
}

ObjScanResult Scanner::finish() {
    for (const ForwardReference& f : forward_) {
        const std::string what = f.what;
        const std::size_t count = what == "position" ? positions_
                                  : what == "normal" ? normals_
                                                     : uvs_;
        if (std::uint64_t(f.index) > count) {
            fail(f.line, f.at + what + " index " + std::to_string(f.index) +
                             " is out of range (the file has " + std::to_string(count) + ")");
        }
    }
    auto& w = result_.warnings;
    if (short_faces_ > 0) {
        w.push_back("line " + std::to_string(short_face_line_) + ": " +
                    std::to_string(short_faces_) +
                    " face(s) of fewer than 3 corners ignored (first here)");
    }
    if (lines_points_ > 0) {
        w.push_back("line " + std::to_string(lines_points_line_) + ": " +
                    std::to_string(lines_points_) +
                    " line/point statement(s) ignored (first here): librt renders triangles only");
    }
    if (unknown_ > 0) {
        w.push_back("line " + std::to_string(unknown_line_) + ": " + std::to_string(unknown_) +
                    " unknown statement(s) ignored (first here: '" + unknown_keyword_ + "')");
    }
    if (faces_ == 0) w.push_back("no faces: the mesh has no triangles");
    result_.face_count = faces_;
    return std::move(result_);
}

}  // namespace

NumberStatus parse_float(std::string_view token, float& value) {
    std::string_view digits = token;
    if (digits.size() > 1 && digits.front() == '+') digits.remove_prefix(1);
    double parsed = 0.0;
    const char* end = digits.data() + digits.size();
    const auto [stop, ec] = std::from_chars(digits.data(), end, parsed);
    if (ec == std::errc::invalid_argument || stop != end) return NumberStatus::Malformed;
    if (ec == std::errc::result_out_of_range) {
        // Too large, or too close to zero for a double: from_chars leaves the value
        // unspecified, strtod tells them apart (HUGE_VAL, or at most DBL_MIN).
        const std::string copy(digits);
        const double fallback = std::strtod(copy.c_str(), nullptr);
        if (!(std::fabs(fallback) <= std::numeric_limits<double>::min())) {
            return NumberStatus::TooLarge;
        }
        value = 0.0f;
        return NumberStatus::Ok;
    }
    if (!std::isfinite(parsed) || std::fabs(parsed) > double(std::numeric_limits<float>::max())) {
        return NumberStatus::TooLarge;
    }
    value = static_cast<float>(parsed);
    return NumberStatus::Ok;
}

void check_obj_head(std::string_view head, const std::string& name) {
    if (head.size() >= 2 &&
        ((head[0] == '\xff' && head[1] == '\xfe') || (head[0] == '\xfe' && head[1] == '\xff'))) {
        throw Error(name + ":1: UTF-16 byte order mark: OBJ files must be ASCII or UTF-8");
    }
    check_nul(head, head.substr(0, 3) == "\xef\xbb\xbf" ? 3 : 0, name);
}

ObjScanResult scan_obj(std::string_view text, const std::string& name,
                       const ObjScanOptions& options) {
    std::size_t skip = 0;
    if (text.size() >= 2 &&
        ((text[0] == '\xff' && text[1] == '\xfe') || (text[0] == '\xfe' && text[1] == '\xff'))) {
        throw Error(name + ":1: UTF-16 byte order mark: OBJ files must be ASCII or UTF-8");
    }
    if (text.substr(0, 3) == "\xef\xbb\xbf") skip = 3;  // UTF-8 byte order mark
    Scanner scanner(text.data(), name, options);
    // Lines end at \n, \r or \r\n, as tinyobjloader reads them, so line numbers agree.
    std::size_t number = 0;
    std::size_t start = skip;
    while (start < text.size()) {
        std::size_t end = start;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        scanner.line(text.substr(start, end - start), ++number);
        if (end < text.size() && text[end] == '\r' && end + 1 < text.size() &&
            text[end + 1] == '\n')
            ++end;
        start = end + 1;
    }
    ObjScanResult result = scanner.finish();
    result.skip = skip;
    return result;
}

}  // namespace librt::detail
