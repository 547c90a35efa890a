// A glTF file is untrusted input (downloaded from anywhere): it may read only the files in
// its own directory tree, its loading takes bounded memory, and its strings reach messages
// escaped and capped. Every file here is written by the test.

#include "io/gltf_test_util.h"
#include "robustness/child_process.h"
#include "robustness/robustness_util.h"

#include <librt/core/untrusted_text.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/io/hdr_image.h>
#include <librt/io/texture_io.h>
#include <librt/loader/scene_file.h>
#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>

#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

using namespace librt;
using librt::testing::ChildResult;
using librt::testing::error_of;
using librt::testing::GltfBuilder;
using librt::testing::has;
using librt::testing::in_child;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// One triangle whose buffer 0 is the external file `uri`; the .bin is written by the
/// caller where `uri` leads.
std::string triangle_with_buffer_uri(const std::string& uri, std::string* bin) {
    GltfBuilder g;
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    g.add_accessor(pos, lt::kFloat, "VEC3", 3);
    g.doc["meshes"] =
        json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}});
    g.doc["nodes"] = json::array({{{"mesh", 0}}});
    g.doc["scenes"] = json::array({{{"nodes", json::array({0})}}});
    *bin = g.bin;
    return g.with_buffer(uri).dump();
}

/// A .gltf whose one texture's image is `uri`.
std::string textured_with_image_uri(const std::string& uri) {
    std::string bin;
    json doc = json::parse(triangle_with_buffer_uri("tri.bin", &bin));
    doc["images"] = json::array({{{"uri", uri}}});
    doc["textures"] = json::array({{{"source", 0}}});
    return doc.dump();
}

/// Loads `path`, expecting an error that names the file, `json_path`, and the refusal.
void expect_outside_refused(const fs::path& path, const std::string& json_path) {
    const std::string msg = error_of([&] { (void)load_gltf(path); });
    EXPECT_TRUE(has(msg, path.string() + ": " + json_path)) << msg;
    EXPECT_TRUE(has(msg, "allow_outside_files")) << msg;
}

}  // namespace

TEST(UntrustedGltf, BufferOutsideTheSceneTreeIsRefused) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "scene");
    std::string bin;
    // The bytes the attack would read: a readable file beside the scene's directory.
    (void)triangle_with_buffer_uri("x", &bin);
    dir.write("secret.bin", bin);
    const fs::path relative =
        dir.write("scene/a.gltf", triangle_with_buffer_uri("../secret.bin", &bin));
    expect_outside_refused(relative, "buffers[0].uri");
    // "sub/../../secret.bin" and a percent-encoded "..".
    expect_outside_refused(
        dir.write("scene/b.gltf", triangle_with_buffer_uri("sub/../../secret.bin", &bin)),
        "buffers[0].uri");
    expect_outside_refused(
        dir.write("scene/c.gltf", triangle_with_buffer_uri("%2e%2e/secret.bin", &bin)),
        "buffers[0].uri");
    const std::string absolute = (dir.path() / "secret.bin").string();
    expect_outside_refused(dir.write("scene/d.gltf", triangle_with_buffer_uri(absolute, &bin)),
                           "buffers[0].uri");
    expect_outside_refused(
        dir.write("scene/e.gltf", triangle_with_buffer_uri("file://" + absolute, &bin)),
        "buffers[0].uri");
    // A symlink inside the tree that leads out of it.
    fs::create_symlink(dir.path() / "secret.bin", dir.path() / "scene" / "link.bin");
    expect_outside_refused(dir.write("scene/f.gltf", triangle_with_buffer_uri("link.bin", &bin)),
                           "buffers[0].uri");
    // A directory symlink too.
    fs::create_directory_symlink(dir.path(), dir.path() / "scene" / "up");
    expect_outside_refused(
        dir.write("scene/g.gltf", triangle_with_buffer_uri("up/secret.bin", &bin)),
        "buffers[0].uri");
    // Other schemes never name a local file.
    const std::string msg = error_of([&] {
        (void)load_gltf(dir.write("scene/h.gltf",
                                  triangle_with_buffer_uri("http://example.invalid/x.bin", &bin)));
    });
    EXPECT_TRUE(has(msg, "buffers[0].uri: 'http://example.invalid/x.bin': only relative paths"))
        << msg;

    // The option lifts the rule for a trusted file; every one of them then loads.
    GltfLoadOptions trusted;
    trusted.allow_outside_files = true;
    for (const char* name : {"a", "b", "c", "d", "e", "f", "g"}) {
        const GltfScene s =
            load_gltf(dir.path() / "scene" / (std::string(name) + ".gltf"), trusted);
        EXPECT_EQ(s.triangles_stored(), 1u) << name;
    }
}

TEST(UntrustedGltf, FilesInsideTheTreeStillLoad) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "scene" / "data");
    std::string bin;
    const std::string json_text = triangle_with_buffer_uri("data/../data/tri.bin", &bin);
    dir.write("scene/data/tri.bin", bin);
    // A symlink that stays inside the tree is followed.
    fs::create_symlink("data/tri.bin", dir.path() / "scene" / "alias.bin");
    EXPECT_EQ(load_gltf(dir.write("scene/a.gltf", json_text)).triangles_stored(), 1u);
    EXPECT_EQ(load_gltf(dir.write("scene/b.gltf", triangle_with_buffer_uri("alias.bin", &bin)))
                  .triangles_stored(),
              1u);
}

TEST(UntrustedGltf, ImageOutsideTheSceneTreeIsRefused) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "scene");
    std::string bin;
    (void)triangle_with_buffer_uri("x", &bin);
    dir.write("scene/tri.bin", bin);
    dir.write("secret.png", lt::tiny_png());
    expect_outside_refused(dir.write("scene/a.gltf", textured_with_image_uri("../secret.png")),
                           "images[0].uri");
    expect_outside_refused(
        dir.write("scene/b.gltf", textured_with_image_uri((dir.path() / "secret.png").string())),
        "images[0].uri");
    // The same image inside the tree decodes.
    dir.write("scene/inside.png", lt::tiny_png());
    const GltfScene s = load_gltf(dir.write("scene/c.gltf", textured_with_image_uri("inside.png")));
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.images[0].width, 2);
    EXPECT_EQ(s.textures[0].image, 0);
    GltfLoadOptions trusted;
    trusted.allow_outside_files = true;
    const GltfScene t = load_gltf(dir.path() / "scene" / "a.gltf", trusted);
    EXPECT_EQ(t.images[0].width, 2);
}

TEST(UntrustedGltf, ImageThatIsADirectoryFifoOrDeviceIsNamedForWhatItIs) {
    // Such an image was once reported as "no such file". Each is a warning (the model
    // renders without that texture), naming the image, its uri and what the path is; a
    // FIFO is never opened (the load would block).
    ScratchDir dir;
    fs::create_directories(dir.path() / "scene" / "sub");
    std::string bin;
    (void)triangle_with_buffer_uri("x", &bin);
    dir.write("scene/tri.bin", bin);
    ASSERT_EQ(::mkfifo((dir.path() / "scene" / "pipe").c_str(), 0600), 0);
    const auto warning_for = [&](const std::string& name, const std::string& uri,
                                 const GltfLoadOptions& options) {
        const fs::path p = dir.write("scene/" + name, textured_with_image_uri(uri));
        const GltfScene s = load_gltf(p, options);
        EXPECT_EQ(s.textures.at(0).image, -1) << uri;
        return lt::joined(s.warnings);
    };
    const GltfLoadOptions plain;
    std::string all = warning_for("d.gltf", "sub", plain);
    EXPECT_TRUE(has(all,
                    "d.gltf: images[0]: 'sub': a directory, not a file; textures using it "
                    "are ignored"))
        << all;
    all = warning_for("f.gltf", "pipe", plain);
    EXPECT_TRUE(has(all, "f.gltf: images[0]: 'pipe': a FIFO, not a file; textures")) << all;
    // A device: a symlink to /dev/zero leads out of the tree and is refused as such...
    fs::create_symlink("/dev/zero", dir.path() / "scene" / "zero");
    const fs::path z = dir.write("scene/z.gltf", textured_with_image_uri("zero"));
    expect_outside_refused(z, "images[0].uri");
    // ...and with files outside allowed, the device itself is named.
    GltfLoadOptions trusted;
    trusted.allow_outside_files = true;
    all = warning_for("z2.gltf", "/dev/zero", trusted);
    EXPECT_TRUE(has(all, "z2.gltf: images[0]: '/dev/zero': a character device, not a file")) << all;
    all = warning_for("z3.gltf", "zero", trusted);
    EXPECT_TRUE(has(all, "a character device, not a file")) << all;
}

TEST(UntrustedGltf, TruncatedJpegImageIsCalledATruncatedJpeg) {
    // stb keeps the last format's complaint: a truncated JPEG was reported as "bad png sig"
    // (the PNG test runs before the JPEG decoder) or "unknown image type".
    ScratchDir dir;
    std::string bin;
    (void)triangle_with_buffer_uri("x", &bin);
    dir.write("tri.bin", bin);
    const std::string jpeg = lt::small_jpeg(64, 64);
    ASSERT_GT(jpeg.size(), 400u);
    // Cut after its frame header (the size reads, the decoding fails) and inside it.
    for (const std::size_t cut : {std::size_t(200), std::size_t(100), jpeg.size() / 2}) {
        const std::string n = std::to_string(cut);
        dir.write("t" + n + ".jpg", jpeg.substr(0, cut));
        const GltfScene s =
            load_gltf(dir.write("t" + n + ".gltf", textured_with_image_uri("t" + n + ".jpg")));
        const std::string all = lt::joined(s.warnings);
        EXPECT_TRUE(has(all, "images[0]: cannot decode: a corrupt or truncated JPEG")) << all;
        EXPECT_FALSE(has(all, "png")) << all;
        EXPECT_FALSE(has(all, "unknown image type")) << all;
        EXPECT_EQ(s.textures.at(0).image, -1);
        // The same file as an OBJ's map_Kd (load_texture).
        const std::string msg =
            error_of([&] { (void)load_texture(dir.path() / ("t" + n + ".jpg")); });
        EXPECT_TRUE(has(msg, "t" + n + ".jpg: a corrupt or truncated JPEG")) << msg;
        EXPECT_FALSE(has(msg, "png")) << msg;
    }
    // The whole file decodes: the JPEG itself is sound.
    dir.write("whole.jpg", jpeg);
    const GltfScene whole =
        load_gltf(dir.write("whole.gltf", textured_with_image_uri("whole.jpg")));
    ASSERT_EQ(whole.textures.at(0).image, 0) << lt::joined(whole.warnings);
    EXPECT_EQ(whole.images[0].width, 64);
}

TEST(UntrustedGltf, SceneGivenWithoutADirectoryCannotReadAbsolutePaths) {
    // A scene path with no directory part once let an absolute uri through as it was.
    ScratchDir dir;
    std::string bin;
    (void)triangle_with_buffer_uri("x", &bin);
    dir.write("secret.bin", bin);
    fs::create_directories(dir.path() / "cwd");
    dir.write("cwd/a.gltf", triangle_with_buffer_uri((dir.path() / "secret.bin").string(), &bin));
    const fs::path before = fs::current_path();
    fs::current_path(dir.path() / "cwd");
    const std::string msg = error_of([&] { (void)load_gltf("a.gltf"); });
    fs::current_path(before);
    EXPECT_TRUE(has(msg, "a.gltf: buffers[0].uri")) << msg;
    EXPECT_TRUE(has(msg, "an absolute path")) << msg;
}

TEST(UntrustedObj, MtlAndTexturesOutsideTheTreeAreRefused) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "scene");
    dir.write("outside.mtl", "newmtl red\nKd 1 0 0\n");
    dir.write("outside.png", lt::tiny_png());
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
    const fs::path a = dir.write("scene/a.obj", "mtllib ../outside.mtl\n" + tri);
    std::string msg = error_of([&] { (void)load_obj(a); });
    EXPECT_TRUE(has(msg, a.string() + ":1: mtllib '../outside.mtl' leads outside")) << msg;
    // A map_Kd in an MTL inside the tree that names a file outside it.
    dir.write("scene/in.mtl",
              "newmtl red\nKd 1 0 0\nmap_Kd " + (dir.path() / "outside.png").string() + "\n");
    const fs::path b = dir.write("scene/b.obj", "mtllib in.mtl\n" + tri);
    msg = error_of([&] { (void)load_obj(b); });
    EXPECT_TRUE(has(msg, "in.mtl: material 'red': map_Kd")) << msg;
    EXPECT_TRUE(has(msg, "leads outside the OBJ's directory")) << msg;
    ObjLoadOptions trusted;
    trusted.allow_outside_files = true;
    const TriangleMesh m = load_obj(a, trusted);
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].diffuse.x, 1.0f);
    EXPECT_NO_THROW((void)load_obj(b, trusted));
    // Inside the tree: loads as before.
    dir.write("scene/tex.png", lt::tiny_png());
    dir.write("scene/ok.mtl", "newmtl red\nKd 1 0 0\nmap_Kd tex.png\n");
    EXPECT_NO_THROW((void)load_obj(dir.write("scene/c.obj", "mtllib ok.mtl\n" + tri)));
}

TEST(UntrustedGltf, QuantizedPositionsNeedTheExtension) {
    // glTF 2.0 section 3.7.2.1: POSITION is FLOAT unless KHR_mesh_quantization is used.
    GltfBuilder g;
    const std::vector<std::int16_t> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    g.add_accessor(pos, lt::kI16, "VEC3", 3);
    g.doc["meshes"] =
        json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}});
    g.doc["nodes"] = json::array({{{"mesh", 0}}});
    ScratchDir dir;
    const fs::path p = dir.write("q.glb", g.glb());
    const std::string msg = error_of([&] { (void)load_gltf(p); });
    EXPECT_TRUE(has(msg, "meshes[0].primitives[0].attributes.POSITION: accessors[0].componentType"))
        << msg;
    EXPECT_TRUE(has(msg, "unless KHR_mesh_quantization is in extensionsUsed")) << msg;
    g.doc["extensionsUsed"] = json::array({"KHR_mesh_quantization"});
    const GltfScene s = load_gltf(dir.write("r.glb", g.glb()));
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].primitives[0].positions[1], glm::vec3(1, 0, 0));
    // Normals as unnormalised bytes are refused even with the extension.
    const std::vector<std::int8_t> normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    g.add_accessor(normals, lt::kI8, "VEC3", 3);
    g.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 1;
    const std::string m2 = error_of([&] { (void)load_gltf(dir.write("s.glb", g.glb())); });
    EXPECT_TRUE(has(m2, "is not allowed for NORMAL")) << m2;
}

TEST(UntrustedGltf, ControlCharactersInNamesAreEscapedAndLongValuesCapped) {
    GltfBuilder g;
    g.doc["materials"] = json::array(
        {{{"name", "red\x1b[31m\a\r\nFORGED LINE"},
          {"alphaMode", std::string("BL\x1b]0;title\aEND") + std::string(100000, 'x')}}});
    ScratchDir dir;
    const std::string msg = error_of([&] { (void)load_gltf(dir.write("c.gltf", g.gltf())); });
    ASSERT_FALSE(msg.empty());
    for (const char c : msg)
        EXPECT_FALSE((static_cast<unsigned char>(c) < 0x20) || c == 0x7f)
            << "control character " << int(c) << " in: " << msg;
    EXPECT_TRUE(has(msg, "\\x1b]0;title\\x07END")) << msg;
    EXPECT_LT(msg.size(), 400u) << "a 100 kB value should be cut to a few dozen bytes";
    // An extension name with a CR/LF in extensionsUsed becomes a warning, escaped.
    GltfBuilder h;
    h.doc["extensionsUsed"] = json::array({"EXT_x\r\nwarning: forged"});
    const GltfScene s = load_gltf(dir.write("d.gltf", h.gltf()));
    const std::string all = lt::joined(s.warnings);
    EXPECT_TRUE(has(all, "extensionsUsed[0]: extension 'EXT_x\\r\\nwarning: forged'")) << all;
    for (const std::string& w : s.warnings)
        for (const char c : w) EXPECT_GE(static_cast<unsigned char>(c), 0x20) << w;
}

namespace {

/// A name carrying what a hostile file would put in one: a colour escape, BEL, CR/LF and a
/// forged line.
const std::string kHostileName = "x\x1b[31m\a\r\nwarning: forged";
/// kHostileName as messages must show it: escaped, on one line.
const std::string kHostileShown = "'x\\x1b[31m\\x07\\r\\nwarning: forged'";

/// Fails for every control character (C0 or DEL) in `text`: a message must be one line
/// that cannot restyle the terminal.
void expect_printable(const std::string& text) {
    for (const char c : text) {
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            ADD_FAILURE() << "control character " << int(c) << " in: " << printable(text);
            return;
        }
    }
}

/// Checks each warning: printable, and short although names of 10,000 bytes went in.
void expect_safe_warnings(const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings) {
        expect_printable(w);
        EXPECT_LT(w.size(), 600u) << "a 10,000-byte name is quoted whole: " << w.substr(0, 300);
    }
}

}  // namespace

TEST(UntrustedGltf, NamesInSceneWarningsAndErrorsAreEscapedAndCapped) {
    // scene_from_gltf's own warnings (nodes and lights scaled to zero, a light's range, a
    // material's ior, an orthographic camera's aspect) once quoted names raw.
    const std::string long_name(10000, 'n');
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_ior"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"name", kHostileName}, {"spot", json::object()}},
        {{"type", "point"}, {"name", long_name}, {"range", 5}}};
    b.doc["materials"] = {
        {{"name", kHostileName}, {"extensions", {{"KHR_materials_ior", {{"ior", 0}}}}}}};
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    b.doc["cameras"] = {
        {{"type", "orthographic"},
         {"name", kHostileName},
         {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 100}}}},
        {{"type", "perspective"},
         {"name", long_name},
         {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
    const json light0 = {{"KHR_lights_punctual", {{"light", 0}}}};
    const json light1 = {{"KHR_lights_punctual", {{"light", 1}}}};
    b.doc["nodes"].push_back({{"mesh", 0}, {"scale", {0, 0, 0}}, {"name", kHostileName}});
    b.doc["nodes"].push_back({{"mesh", 0}, {"scale", {0, 0, 0}}, {"name", long_name}});
    b.doc["nodes"].push_back({{"scale", {0, 0, 0}}, {"extensions", light0}});
    b.doc["nodes"].push_back({{"translation", {0, 2, 0}}, {"extensions", light1}});
    b.doc["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 3}}});
    b.doc["nodes"].push_back({{"camera", 1}, {"translation", {0, 0, 4}}});
    b.doc["scenes"][0]["nodes"] = {0, 1, 2, 3, 4, 5, 6};
    ScratchDir dir;
    const fs::path p = dir.write("names.gltf", b.gltf());
    SceneFileOptions options;
    options.width = 40;  // 2:1 against the orthographic camera's 1:1: a warning
    options.height = 20;

    const LoadedScene loaded = load_scene_file(p, options);
    const std::string all = lt::joined(loaded.warnings);
    EXPECT_TRUE(has(all, "nodes[1] " + kHostileShown + ": its world transform is singular")) << all;
    EXPECT_TRUE(has(all, "nodes[2] 'nnnnn")) << all;
    EXPECT_TRUE(has(all, "extensions.KHR_lights_punctual.lights[0] " + kHostileShown +
                             " placed by nodes[3]: its world transform is singular"))
        << all;
    EXPECT_TRUE(has(all, "extensions.KHR_lights_punctual.lights[1] 'nnnnn")) << all;
    EXPECT_TRUE(has(all, "materials[0] " + kHostileShown + ": KHR_materials_ior 0")) << all;
    EXPECT_TRUE(has(all, "orthographic camera " + kHostileShown + ": xmag / ymag")) << all;
    expect_safe_warnings(loaded.warnings);
    // The name itself is kept as the file gives it (the app quotes it when it prints it).
    EXPECT_EQ(loaded.camera_name, kHostileName);

    // scene_from_gltf called directly: the same, and the GltfScene keeps the real names.
    GltfScene gltf = load_gltf(p);
    ASSERT_GE(gltf.instances.size(), 3u);
    EXPECT_EQ(gltf.instances[1].node_name, kHostileName);
    EXPECT_EQ(gltf.instances[2].node_name, long_name);
    expect_safe_warnings(scene_from_gltf(std::move(gltf), options).warnings);

    // An error that lists the cameras, and one naming the camera it refuses.
    options.camera = "no such";
    std::string msg = error_of([&] { (void)load_scene_file(p, options); });
    EXPECT_TRUE(has(msg, "(cameras: 0 " + kHostileShown + ", 1 'nnnn")) << msg;
    EXPECT_LT(msg.size(), 600u) << msg.substr(0, 300);
    b.doc["nodes"][5]["scale"] = {0, 0, 0};
    options.camera.clear();
    msg = error_of([&] { (void)load_scene_file(dir.write("flat.gltf", b.gltf()), options); });
    EXPECT_TRUE(has(msg, "cameras[0] " + kHostileShown + " placed by nodes[5]: its world")) << msg;
}

TEST(UntrustedObj, MtlMaterialNamesAreEscapedAndTheirMessagesNameTheFile) {
    // add_mesh_with_mtl's warning for a texture that does not load once quoted the MTL
    // name raw and did not say which file defined it.
    ScratchDir dir;
    const std::string long_name(10000, 'm');
    // ESC and BEL stay in an MTL name (CR and LF end its line).
    const std::string name = "red\x1b[31m\aX";
    dir.write("m.mtl", "newmtl " + name + "\nKd 1 0 0\nmap_Kd missing.png\n\nnewmtl " + long_name +
                           "\nKd 0 1 0\nmap_Kd gone.png\n");
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    const fs::path obj = dir.write("m.obj", "mtllib m.mtl\n" + tri + "usemtl " + name +
                                                "\nf 1 2 3\nusemtl " + long_name + "\nf 1 3 2\n");
    const std::string mtl = (dir.path() / "m.mtl").string();
    const std::string shown = "'red\\x1b[31m\\x07X'";

    const LoadedScene loaded = load_scene_file(obj);
    const std::string all = lt::joined(loaded.warnings);
    EXPECT_TRUE(has(all, mtl + ":1: MTL material " + shown + ": cannot load texture")) << all;
    EXPECT_TRUE(has(all, mtl + ":5: MTL material 'mmmm")) << all;
    EXPECT_TRUE(has(all, "using its Kd instead")) << all;
    expect_safe_warnings(loaded.warnings);

    // Through the library call itself, and the mesh keeps the names as they are.
    const TriangleMesh mesh = load_obj(obj);
    ASSERT_GE(mesh.materials.size(), 2u);
    EXPECT_EQ(mesh.materials[0].name, name);
    EXPECT_EQ(mesh.materials[0].defined_at, mtl + ":1");
    Scene scene;
    const std::uint32_t fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const MtlMeshResult added = add_mesh_with_mtl(scene, mesh, fallback);
    ASSERT_EQ(added.warnings.size(), 2u);
    EXPECT_TRUE(has(added.warnings[0], mtl + ":1: MTL material " + shown)) << added.warnings[0];
    expect_safe_warnings(added.warnings);

    // A value no Material accepts: the error names the file and line too.
    dir.write("bad.mtl", "# lamp\nnewmtl " + name + "\nKd 1.5 0 0\n");
    const fs::path bad =
        dir.write("bad.obj", "mtllib bad.mtl\n" + tri + "usemtl " + name + "\nf 1 2 3\n");
    const std::string msg = error_of([&] { (void)load_scene_file(bad); });
    EXPECT_TRUE(has(msg, (dir.path() / "bad.mtl").string() + ":2: MTL material " + shown + ": "))
        << msg;
}

TEST(UntrustedText, PrintableEscapesAndCuts) {
    EXPECT_EQ(printable("a\x1b[0m\tb\n"), "a\\x1b[0m\\tb\\n");
    EXPECT_EQ(printable("caf\xc3\xa9"), "caf\xc3\xa9");  // valid UTF-8 kept
    EXPECT_EQ(printable("\xc2\x9b"
                        "31m"),
              "\\u009b31m");                                  // C1 CSI
    EXPECT_EQ(printable("\xff\xc3"), "\\xff\\xc3");           // not UTF-8
    EXPECT_EQ(printable("\xe0\x80\xaf"), "\\xe0\\x80\\xaf");  // overlong '/'
    EXPECT_EQ(printable("abcdef", 4), "abcd\xE2\x80\xA6");
    EXPECT_EQ(printable("\xc3\xa9\xc3\xa9", 3), "\xc3\xa9\xE2\x80\xA6");  // cut between chars
    EXPECT_EQ(quote_untrusted(std::string(200, 'y')).size(), 1 + kMaxQuotedBytes + 3 + 1);
    EXPECT_EQ(std::string(Error(std::string(100000, 'z')).what()).size(), kMaxErrorBytes + 3);
    EXPECT_EQ(std::string(Error("x\ny").what()), "x\\ny");
}

// ---- memory: peak of loading <= 16 x the bytes read + 256 MiB, or a clear error ----

namespace {

/// Loads `path` in a child: it must load or fail with a librt::Error, and its peak memory
/// must stay within the bound for `files_read` bytes of files.
ChildResult expect_bounded_load(const fs::path& path, std::uint64_t files_read) {
    const ChildResult r = in_child([&] { (void)load_gltf(path); });
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << "crashed: " << r.exit_code;
    const std::uint64_t bound = 16 * files_read + (std::uint64_t{256} << 20u);
    EXPECT_LE(r.peak_added, bound)
        << path << ": peak " << r.peak_added << " bytes, bound " << bound << "; " << r.message;
    return r;
}

}  // namespace

TEST(UntrustedGltfMemory, LargeExtrasCostNothing) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "peak resident memory is not the program's own under a sanitizer "
                    "(shadow memory, quarantine); measured in the release stage";
#endif
    // 15 MB of "0," in an extras array: once 0.94 GB at peak.
    GltfBuilder g;
    std::string text = g.doc.dump();
    text.pop_back();
    text += R"(,"extras":{"payload":[)";
    for (int i = 0; i < 7'500'000; ++i) text += "0,";
    text += "0]}}";
    ScratchDir dir;
    const fs::path p = dir.write("extras.gltf", text);
    const ChildResult r = expect_bounded_load(p, text.size());
    EXPECT_EQ(r.exit_code, 0) << r.message;
    // Far below the bound: the extras are never built.
    EXPECT_LT(r.peak_added, 4 * text.size()) << r.peak_added;
}

TEST(UntrustedGltfMemory, ManyImagesNamingOneFileReadItOnce) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "peak resident memory is not the program's own under a sanitizer "
                    "(shadow memory, quarantine); measured in the release stage";
#endif
    // 100 images (each used by a texture) naming one 10 MB file: once 1 GB at peak.
    ScratchDir dir;
    std::string bin;
    json doc = json::parse(triangle_with_buffer_uri("tri.bin", &bin));
    dir.write("tri.bin", bin);
    const std::string big(10u << 20u, 'q');  // not an image: each decode fails
    dir.write("big.png", big);
    for (int i = 0; i < 100; ++i) {
        doc["images"].push_back({{"uri", "big.png"}});
        doc["textures"].push_back({{"source", i}});
    }
    const fs::path p = dir.write("many.gltf", doc.dump());
    const ChildResult r = expect_bounded_load(p, doc.dump().size() + bin.size() + big.size());
    EXPECT_EQ(r.exit_code, 0) << r.message;
    EXPECT_LT(r.peak_added, 4 * big.size()) << "the file was read more than once";
    // Once in the parent too: one warning for the file, every texture unusable.
    const GltfScene s = load_gltf(p);
    EXPECT_EQ(s.warnings.size(), 1u) << lt::joined(s.warnings);
    for (const GltfTexture& t : s.textures) EXPECT_EQ(t.image, -1);
}

TEST(UntrustedGltfMemory, AMillionNodesStayWithinTheBoundOrAreRefused) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "peak resident memory is not the program's own under a sanitizer "
                    "(shadow memory, quarantine); measured in the release stage";
#endif
    GltfBuilder g;
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    g.add_accessor(pos, lt::kFloat, "VEC3", 3);
    g.doc["meshes"] =
        json::array({{{"primitives", json::array({{{"attributes", {{"POSITION", 0}}}}})}}});
    // Written as text: a million-element nlohmann tree would take the test itself seconds.
    std::string text = g.with_buffer("").dump();
    text.pop_back();
    text += R"(,"nodes":[)";
    for (int i = 0; i < 1'000'000; ++i) text += i == 0 ? R"({"mesh":0})" : R"(,{"mesh":0})";
    text += R"(],"scenes":[{"nodes":[)";
    for (int i = 0; i < 1'000'000; ++i) {
        if (i != 0) text += ',';
        text += std::to_string(i);
    }
    text += "]}]}";
    ScratchDir dir;
    const std::string glb = GltfBuilder::make_glb(text, g.bin);
    const fs::path p = dir.write("nodes.glb", glb);
    const ChildResult r = expect_bounded_load(p, glb.size());
    if (r.exit_code == 1) {
        EXPECT_TRUE(has(r.message, "nodes.glb: loading would take")) << r.message;
    }
}

TEST(UntrustedGltfMemory, AllocationFailureIsAnErrorNotAnAbort) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "a sanitizer reserves terabytes of address space: RLIMIT_AS cannot "
                    "limit it; checked in the release stage";
#endif
    // A million nodes under an address-space limit far below what they need, with the
    // loader's own bound lifted: allocation fails inside tinygltf. Once SIGABRT.
    std::string text = R"({"asset":{"version":"2.0"},"nodes":[)";
    for (int i = 0; i < 1'000'000; ++i) text += i == 0 ? R"({"name":"n"})" : R"(,{"name":"n"})";
    text += "]}";
    ScratchDir dir;
    const fs::path p = dir.write("nodes.gltf", text);
    GltfLoadOptions unbounded;
    unbounded.max_memory_bytes = std::uint64_t{1} << 40u;
    // Failing at different stages: JSON tree, tinygltf's tree, its Model.
    for (const std::uint64_t headroom_mib : {40u, 150u, 400u}) {
        const ChildResult r = in_child([&] { (void)load_gltf(p, unbounded); }, headroom_mib << 20u);
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1)
            << headroom_mib << " MiB: crashed with exit " << r.exit_code;
        if (headroom_mib == 40) {
            EXPECT_EQ(r.exit_code, 1) << "expected a librt::Error";
        }
        if (r.exit_code == 1) {
            EXPECT_TRUE(has(r.message, "nodes.gltf: out of memory while loading")) << r.message;
        }
    }
}

// ---- out of memory in the other loaders: an Error naming the file, never bad_alloc ----
// Once, an OBJ scene, an --env sky or the build of a loaded scene under a memory limit
// let std::bad_alloc out: the apps said "internal error: std::bad_alloc".

namespace {

/// An OBJ of a flat n x n grid of quads (2 n^2 triangles): about 45 bytes a triangle.
std::string grid_obj(int n) {
    std::string text;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            text += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
    const auto at = [n](int x, int y) { return std::to_string(y * (n + 1) + x + 1); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            text += "f " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + "\nf " +
                    at(x, y) + " " + at(x + 1, y + 1) + " " + at(x, y + 1) + "\n";
    return text;
}

/// Runs `load` in children under address-space limits of the parent's size plus each of
/// `headroom_mib`: every child must load or fail with a librt::Error (never crash), the
/// smallest headroom must fail, and every failure must read `expected`. ctest runs each
/// test in a fresh process, as this needs: after many other tests in one process, the
/// arenas their threads left (free memory already mapped) can serve a loader's threads
/// under any limit.
void expect_out_of_memory_errors(const std::function<void()>& load,
                                 std::initializer_list<std::uint64_t> headroom_mib,
                                 const std::string& expected) {
    bool first = true;
    for (const std::uint64_t mib : headroom_mib) {
        const ChildResult r = in_child(load, mib << 20u);
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1)
            << mib << " MiB: crashed with exit " << r.exit_code;
        if (first) {
            EXPECT_EQ(r.exit_code, 1) << mib << " MiB: expected a librt::Error";
        }
        if (r.exit_code == 1) {
            EXPECT_TRUE(has(r.message, expected)) << mib << " MiB: " << r.message;
        }
        first = false;
    }
}

}  // namespace

TEST(OutOfMemory, ObjSceneIsAnErrorNamingTheFile) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "a sanitizer reserves terabytes of address space: RLIMIT_AS cannot "
                    "limit it; checked in the release stage";
#endif
    ScratchDir dir;
    const std::string text = grid_obj(300);  // 180 000 triangles, about 8 MB
    const fs::path p = dir.write("grid.obj", text);
    // Failing at different stages: reading the file, tinyobjloader's arrays, the mesh.
    expect_out_of_memory_errors([&] { (void)load_scene_file(p); }, {4, 24, 48, 96},
                                p.string() + ": out of memory while loading (allocation failed)");
}

TEST(OutOfMemory, EnvironmentMapIsAnErrorNamingTheFile) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "a sanitizer reserves terabytes of address space: RLIMIT_AS cannot "
                    "limit it; checked in the release stage";
#endif
    // 4096 x 2048 texels of one colour run-length coded: 550 KB decoding to 100 MB of
    // stb's floats, then 100 MB of image (within the loading bound).
    std::string bytes = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2048 +X 4096\n";
    std::string line = {2, 2, char(4096 >> 8), char(4096 & 0xFF)};
    for (const char value : {char(128), char(128), char(128), char(129)}) {
        for (int x = 0; x < 4096; x += 127) {
            line += char(128 + std::min(127, 4096 - x));
            line += value;
        }
    }
    for (int y = 0; y < 2048; ++y) bytes += line;
    ScratchDir dir;
    const fs::path p = dir.write("sky.hdr", bytes);
    // Failing in stb's malloc (its "outofmem"), then in the image's vector; with room for
    // both it loads (the file is valid).
    expect_out_of_memory_errors([&] { (void)load_hdr_image(p); }, {4, 140},
                                "cannot load HDR image " + p.string() +
                                    ": out of memory while loading (allocation failed)");
    EXPECT_EQ(in_child([&] { (void)load_hdr_image(p); }, 400u << 20u).exit_code, 0);
}

TEST(OutOfMemory, CommittingALoadedSceneIsAnError) {
#ifdef LIBRT_TEST_SANITIZED
    GTEST_SKIP() << "a sanitizer reserves terabytes of address space: RLIMIT_AS cannot "
                    "limit it; checked in the release stage";
#endif
    ScratchDir dir;
    const fs::path p = dir.write("grid.obj", grid_obj(300));
    // Loaded in full, then the limit: the BVH build (threads, scratch arrays) runs out.
    for (const std::uint64_t mib : {2u, 16u, 32u}) {
        const ChildResult r = in_child([&] {
            LoadedScene loaded = load_scene_file(p);
            lt::limit_address_space(mib << 20u);
            loaded.scene.commit();
        });
        EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1)
            << mib << " MiB: crashed with exit " << r.exit_code;
        if (mib == 2) {
            EXPECT_EQ(r.exit_code, 1) << "expected a librt::Error";
        }
        if (r.exit_code == 1) {
            EXPECT_TRUE(has(r.message, "Scene::commit: out of memory while building")) << r.message;
        }
    }
}
