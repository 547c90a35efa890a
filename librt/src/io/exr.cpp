// OpenEXR through tinyexr rather than OpenEXR's own library: Debian's libtinyexr-dev is a
// small C API in one shared library (libtinyexr.so, built against the system zlib, so no
// TINYEXR_IMPLEMENTATION and no bundled miniz here), it writes and reads multi-channel
// half/float scan-line files with ZIP compression, which is all librt needs, and it costs
// one imported target; libopenexr-dev would add OpenEXR 3, Imath and a C++ ABI to track
// for the same result.

#include <librt/core/error.h>
#include <librt/io/exr.h>

#include <glm/vec3.hpp>
#include <tinyexr.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace librt {

namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) {
    std::string out(1, '\'');  // appended piecewise: g++ 12 warns (-Wrestrict) on "'" + s
    out += path.string();
    out += '\'';
    return out;
}

// Writes `size` bytes to a temporary file beside `path` and renames it over `path`, so
// the target is either untouched or complete. Deliberately small and local: io/ is getting
// one shared atomic-write helper, which this is meant to be replaced by.
void write_file_atomically(const fs::path& path, const unsigned char* data, std::size_t size) {
    if (path.filename().empty()) throw Error("cannot write " + quoted(path) + ": no file name");
    static std::atomic<unsigned long long> counter{0};
    const auto now = static_cast<unsigned long long>(
        std::chrono::steady_clock::now().time_since_epoch().count());
    const auto thread =
        static_cast<unsigned long long>(std::hash<std::thread::id>{}(std::this_thread::get_id()));
    char suffix[80];
    std::snprintf(suffix, sizeof suffix, ".tmp-%llx-%llx-%llu", now, thread,
                  counter.fetch_add(1, std::memory_order_relaxed));
    std::string temp_name(1, '.');
    temp_name += path.filename().string();
    temp_name += suffix;
    const fs::path temp = path.parent_path() / temp_name;
    std::FILE* file = std::fopen(temp.string().c_str(), "wbx");  // x: never reuse a file
    if (file == nullptr) throw Error("cannot write " + quoted(path) + ": " + std::strerror(errno));
    bool ok = std::fwrite(data, 1, size, file) == size;
    ok = std::fflush(file) == 0 && ok;
    const int saved_errno = ok ? 0 : errno;
    ok = std::fclose(file) == 0 && ok;
    std::error_code ec;
    if (ok) fs::rename(temp, path, ec);
    if (!ok || ec) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        throw Error(
            "cannot write " + quoted(path) + ": " +
            (ec ? ec.message()
                : std::string(saved_errno != 0 ? std::strerror(saved_errno) : "write failed")));
    }
}

// One channel to write: its name, storage type and width * height values.
struct Channel {
    std::string name;
    int type = TINYEXR_PIXELTYPE_FLOAT;
    std::vector<float> values;
};

void check_layer_size(const fs::path& path, const char* layer, std::size_t size,
                      std::size_t expected) {
    if (size != expected) {
        throw Error("cannot write " + quoted(path) + ": layer " + layer + " has " +
                    std::to_string(size) + " pixels, the beauty " + std::to_string(expected));
    }
}

void check_no_nan(const fs::path& path, const Channel& channel, int width) {
    const auto it = std::find_if(channel.values.begin(), channel.values.end(),
                                 [](float v) { return std::isnan(v); });
    if (it != channel.values.end()) {
        const auto i = static_cast<long long>(it - channel.values.begin());
        throw Error("cannot write " + quoted(path) + ": channel " + channel.name +
                    " is NaN at pixel (" + std::to_string(i % width) + ", " +
                    std::to_string(i / width) + ")");
    }
}

// The three planes of an RGB image, named prefix + names[i].
void add_rgb(std::vector<Channel>& channels, const Image& image, const std::string& prefix,
             const char* names, int type) {
    for (int c = 0; c < 3; ++c) {
        Channel channel{prefix + names[c], type, {}};
        channel.values.resize(image.pixels.size());
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
            channel.values[i] = image.pixels[i][c];
        channels.push_back(std::move(channel));
    }
}

// The largest finite half, (2 - 2^-10) x 2^15 (IEEE 754 binary16): tinyexr rounds anything
// from 65520 up, and an infinity, to an infinite half.
constexpr float kMaxHalf = 65504.0f;

// Clamps the half channels named prefix + names[i] (the last three added) to +-65504; a
// warning naming the layer when any value was larger.
void clamp_to_half(std::vector<Channel>& channels, const fs::path& path, const char* layer,
                   std::vector<std::string>& warnings) {
    std::size_t clamped = 0;
    float largest = 0.0f;
    for (std::size_t c = channels.size() - 3; c < channels.size(); ++c) {
        for (float& v : channels[c].values) {
            if (std::fabs(v) > kMaxHalf) {  // false for NaN, refused later
                ++clamped;
                largest = std::max(largest, std::fabs(v));
                v = std::copysign(kMaxHalf, v);
            }
        }
    }
    if (clamped == 0) return;
    char text[160];
    std::snprintf(text, sizeof text,
                  ": %zu %s value(s) above 65504, the largest half float, clamped to it "
                  "(largest %g); write float channels to keep them",
                  clamped, layer, double(largest));
    warnings.push_back(quoted(path) + text);
}

struct ErrorMessage {
    const char* text = nullptr;
    ~ErrorMessage() {
        if (text != nullptr) FreeEXRErrorMessage(text);
    }
    [[nodiscard]] std::string str() const { return text != nullptr ? text : "unknown error"; }
};

}  // namespace

ExrWriteResult write_exr(const fs::path& path, const ImageLayers& layers,
                         const ExrWriteOptions& options) {
    const Image& beauty = layers.beauty;
    const auto pixel_count = static_cast<std::size_t>(std::max(beauty.width, 0)) *
                             static_cast<std::size_t>(std::max(beauty.height, 0));
    if (beauty.width < 1 || beauty.height < 1 || beauty.pixels.size() != pixel_count) {
        throw Error("cannot write " + quoted(path) + ": beauty is " + std::to_string(beauty.width) +
                    " x " + std::to_string(beauty.height) + " with " +
                    std::to_string(beauty.pixels.size()) + " pixels");
    }
    const bool half = options.colour == ExrPixelType::Half;
    const int colour = half ? TINYEXR_PIXELTYPE_HALF : TINYEXR_PIXELTYPE_FLOAT;
    ExrWriteResult result;
    std::vector<Channel> channels;
    add_rgb(channels, beauty, "", "RGB", colour);
    if (half) clamp_to_half(channels, path, "beauty", result.warnings);
    if (!layers.albedo.pixels.empty() || layers.albedo.width != 0) {
        check_layer_size(path, "albedo", layers.albedo.pixels.size(), pixel_count);
        add_rgb(channels, layers.albedo, "albedo.", "RGB", colour);
        if (half) clamp_to_half(channels, path, "albedo", result.warnings);
    }
    if (!layers.normal.pixels.empty() || layers.normal.width != 0) {
        check_layer_size(path, "normal", layers.normal.pixels.size(), pixel_count);
        add_rgb(channels, layers.normal, "normal.", "XYZ", colour);
        if (half) clamp_to_half(channels, path, "normal", result.warnings);
    }
    if (!layers.denoised.pixels.empty() || layers.denoised.width != 0) {
        check_layer_size(path, "denoised", layers.denoised.pixels.size(), pixel_count);
        add_rgb(channels, layers.denoised, "denoised.", "RGB", colour);
        if (half) clamp_to_half(channels, path, "denoised", result.warnings);
    }
    // Depth and the sample count stay 32-bit whatever options.colour says (exr.h).
    if (!layers.depth.empty()) {
        check_layer_size(path, "depth", layers.depth.size(), pixel_count);
        channels.push_back({"Z", TINYEXR_PIXELTYPE_FLOAT, layers.depth});
    }
    if (!layers.sample_count.empty()) {
        check_layer_size(path, "sample_count", layers.sample_count.size(), pixel_count);
        channels.push_back({"sample_count", TINYEXR_PIXELTYPE_FLOAT, layers.sample_count});
    }
    for (const Channel& channel : channels) check_no_nan(path, channel, beauty.width);
    // OpenEXR stores the channel list sorted by name (byte order); tinyexr writes it in
    // the order given.
    std::sort(channels.begin(), channels.end(),
              [](const Channel& a, const Channel& b) { return a.name < b.name; });

    std::vector<EXRChannelInfo> infos(channels.size());
    std::vector<int> input_types(channels.size(), TINYEXR_PIXELTYPE_FLOAT);
    std::vector<int> stored_types(channels.size());
    std::vector<unsigned char*> planes(channels.size());
    for (std::size_t c = 0; c < channels.size(); ++c) {
        std::memset(&infos[c], 0, sizeof(EXRChannelInfo));
        std::snprintf(infos[c].name, sizeof infos[c].name, "%s", channels[c].name.c_str());
        stored_types[c] = channels[c].type;
        planes[c] = reinterpret_cast<unsigned char*>(channels[c].values.data());
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = static_cast<int>(channels.size());
    header.channels = infos.data();
    header.pixel_types = input_types.data();             // what `planes` hold
    header.requested_pixel_types = stored_types.data();  // what the file stores
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = header.num_channels;
    image.images = planes.data();
    image.width = beauty.width;
    image.height = beauty.height;

    unsigned char* memory = nullptr;
    ErrorMessage error;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error.text);
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    if (size == 0 || memory == nullptr) {
        throw Error("cannot write " + quoted(path) + ": tinyexr: " + error.str());
    }
    write_file_atomically(path, memory, size);
    return result;
}

ImageLayers read_exr(const fs::path& path) {
    const std::string name = path.string();
    EXRVersion version;
    const int version_status = ParseEXRVersionFromFile(&version, name.c_str());
    if (version_status == TINYEXR_ERROR_CANT_OPEN_FILE) {
        throw Error("cannot read " + quoted(path) + ": cannot open the file");
    }
    if (version_status != TINYEXR_SUCCESS) {
        throw Error("cannot read " + quoted(path) + ": not an OpenEXR file");
    }
    if (version.multipart != 0 || version.tiled != 0 || version.non_image != 0) {
        throw Error("cannot read " + quoted(path) +
                    ": only single-part scan-line OpenEXR files are supported");
    }
    EXRHeader header;
    InitEXRHeader(&header);
    const std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> header_guard(&header, &FreeEXRHeader);
    ErrorMessage error;
    if (ParseEXRHeaderFromFile(&header, &version, name.c_str(), &error.text) != TINYEXR_SUCCESS) {
        throw Error("cannot read " + quoted(path) + ": " + error.str());
    }
    // Half channels are widened to float on load; float and uint ones come as stored.
    for (int c = 0; c < header.num_channels; ++c) {
        if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
            header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    }
    EXRImage image;
    InitEXRImage(&image);
    const std::unique_ptr<EXRImage, int (*)(EXRImage*)> image_guard(&image, &FreeEXRImage);
    if (LoadEXRImageFromFile(&image, &header, name.c_str(), &error.text) != TINYEXR_SUCCESS) {
        throw Error("cannot read " + quoted(path) + ": " + error.str());
    }
    if (image.images == nullptr) {
        throw Error("cannot read " + quoted(path) + ": no scan-line pixel data");
    }
    check_image_size(image.width, image.height);
    const auto count =
        static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);

    std::map<std::string, int> index;
    for (int c = 0; c < header.num_channels; ++c) index[header.channels[c].name] = c;
    // Channel `name` as floats, or empty when the file has no such channel.
    const auto plane = [&](const std::string& channel) {
        std::vector<float> values;
        const auto it = index.find(channel);
        if (it == index.end()) return values;
        values.resize(count);
        const unsigned char* data = image.images[it->second];
        if (header.requested_pixel_types[it->second] == TINYEXR_PIXELTYPE_UINT) {
            std::vector<std::uint32_t> raw(count);
            std::memcpy(raw.data(), data, count * sizeof(std::uint32_t));
            std::transform(raw.begin(), raw.end(), values.begin(),
                           [](std::uint32_t v) { return static_cast<float>(v); });
        } else {
            std::memcpy(values.data(), data, count * sizeof(float));
        }
        return values;
    };
    const auto rgb = [&](const std::string& prefix, const char* names) {
        const std::vector<float> a = plane(prefix + names[0]);
        const std::vector<float> b = plane(prefix + names[1]);
        const std::vector<float> c = plane(prefix + names[2]);
        Image result;
        if (a.empty() || b.empty() || c.empty()) return result;
        result = Image(image.width, image.height);
        for (std::size_t i = 0; i < count; ++i) result.pixels[i] = glm::vec3(a[i], b[i], c[i]);
        return result;
    };
    ImageLayers layers;
    layers.beauty = rgb("", "RGB");
    if (layers.beauty.pixels.empty()) {
        throw Error("cannot read " + quoted(path) + ": no R, G, B channels");
    }
    layers.albedo = rgb("albedo.", "RGB");
    layers.normal = rgb("normal.", "XYZ");
    layers.denoised = rgb("denoised.", "RGB");
    layers.depth = plane("Z");
    layers.sample_count = plane("sample_count");
    return layers;
}

}  // namespace librt
