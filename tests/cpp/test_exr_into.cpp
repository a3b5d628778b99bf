// Writing into copies of the input (sf_write_options.into, the CLI's --into): the filtered channels
// go back in place; every other part comes out bit for bit, every other channel of the changed part
// as it was, every header kept. Files are written here with OpenImageIO and inspected with it.
#include <gtest/gtest.h>

#include <filesystem>

#include "capi_util.hpp"
#include "exr_util.hpp"

using namespace statfilter_test;

namespace {

constexpr int kW = 12, kH = 8;
const std::vector<std::string> kLight = {"ViewLayer.Diffuse Indirect.R", "ViewLayer.Diffuse Indirect.G",
                                         "ViewLayer.Diffuse Indirect.B"};

// Blender-like frames: part 0 the beauty with its render statistics, part 1 the light pass (a region
// of the frame, PIZ), part 2 the normals; half floats as renderers write them.
class IntoCopies : public ::testing::Test {
protected:
    void SetUp() override {
        std::filesystem::create_directory(dir.path() / "out");
        for (int64_t f = 1; f <= 4; ++f) {
            ExrPart beauty{"ViewLayer.Combined",
                           {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B"},
                           make_pixels(kW, kH, 3, f)};
            beauty.attributes = {{"cycles.ViewLayer.samples", "16"}, {"camera", "Camera.001"}};
            ExrPart light{"ViewLayer.Diffuse Indirect", kLight, make_pixels(10, 6, 3, f, 0.25f)};
            light.x = 1, light.y = 2, light.data_width = 10, light.data_height = 6;
            light.attributes = {{"note", "the light"}};
            light.compression = "piz";
            ExrPart normal{"ViewLayer.Normal", {"ViewLayer.Normal.X", "ViewLayer.Normal.Y", "ViewLayer.Normal.Z"},
                           make_pixels(kW, kH, 3, f, -0.5f)};
            write_exr(frame("in", f), kW, kH, {beauty, light, normal}, OIIO::TypeDesc::HALF);
        }
    }
    std::string frame(const std::string& name, int64_t f) const {
        return dir.file((name == "in" ? "" : "out/") + name + ".000" + std::to_string(f) + ".exr");
    }
    // pca rank 1 over the channels read, into copies or to new files (half, as the input).
    sf_status run(const char* channels, const std::string& out, bool into, sf_write_options* write = nullptr) {
        sf_filter raw = nullptr;
        EXPECT_SF_OK(sf_filter_create("pca", &raw));
        Filt f(raw);
        EXPECT_SF_OK(sf_filter_set_string(f.get(), "rank", "1"));
        sf_read_options r;
        sf_read_options_init(&r);
        r.channels = channels;
        sf_write_options w;
        sf_write_options_init(&w);
        if (write) w = *write;
        w.into = into ? 1 : 0;
        const sf_status status = sf_filter_run(f.get(), dir.file("in.####.exr").c_str(), &r, out.c_str(), &w, nullptr);
        message = sf_filter_last_error(f.get());
        return status;
    }
    std::string message;  // the filter's last error
    TempDir dir;
};

int part_count(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    int n = 0;
    while (in && in->seek_subimage(n, 0)) ++n;
    return n;
}

}  // namespace

TEST_F(IntoCopies, TheLightGoesBackAndEveryOtherPartIsAsItWas) {
    ASSERT_SF_OK(run("ViewLayer.Diffuse Indirect", dir.file("out/into.####.exr"), true));
    ASSERT_SF_OK(run("ViewLayer.Diffuse Indirect", dir.file("out/new.####.exr"), false));
    for (int64_t f = 1; f <= 4; ++f) {
        const std::string in = frame("in", f), into = frame("into", f);
        ASSERT_EQ(part_count(into), 3);
        for (int part : {0, 2}) {  // untouched: the same pixels and header
            const ExrImage a = read_exr(in, part), b = read_exr(into, part);
            EXPECT_EQ(a.pixels, b.pixels) << "frame " << f << " part " << part;
            EXPECT_EQ(a.spec.channelnames, b.spec.channelnames);
            EXPECT_EQ(b.spec.get_string_attribute("statfilter:filter"), "");
        }
        const ExrImage light_in = read_exr(in, 1), light = read_exr(into, 1), fresh = read_exr(frame("new", f));
        EXPECT_EQ(light.spec.format, OIIO::TypeDesc::HALF);
        EXPECT_EQ(light.spec.get_string_attribute("compression"), "piz");
        EXPECT_EQ(light.spec.get_string_attribute("note"), "the light");
        EXPECT_EQ(light.spec.get_string_attribute("oiio:subimagename"), "ViewLayer.Diffuse Indirect");
        EXPECT_EQ(light.spec.get_string_attribute("statfilter:filter"), "pca");
        EXPECT_EQ(light.spec.get_string_attribute("statfilter:parameters"), "rank=1");
        EXPECT_EQ(light.spec.x, 1);
        EXPECT_EQ(light.spec.y, 2);
        EXPECT_EQ(light.spec.width, 10);
        EXPECT_EQ(light.spec.channelnames, kLight);
        EXPECT_EQ(light.pixels, fresh.pixels) << "frame " << f << ": the same answer as a new file";
        EXPECT_NE(light.pixels, light_in.pixels) << "frame " << f << ": the light was filtered";
        const ExrImage beauty = read_exr(into, 0);
        EXPECT_EQ(beauty.spec.get_string_attribute("cycles.ViewLayer.samples"), "16");
        EXPECT_EQ(beauty.spec.get_string_attribute("camera"), "Camera.001");
    }
}

// One part holding two layers (as Blender writes single-part multilayer files): the normals beside
// the light are kept, sample for sample.
TEST_F(IntoCopies, OtherChannelsOfTheSamePartStay) {
    std::vector<std::string> names = kLight;
    for (const char* c : {"X", "Y", "Z"}) names.push_back(std::string("ViewLayer.Normal.") + c);
    for (int64_t f = 1; f <= 4; ++f)
        write_exr(frame("in", f), kW, kH, {ExrPart{"", names, make_pixels(kW, kH, 6, f)}}, OIIO::TypeDesc::FLOAT);
    ASSERT_SF_OK(run(nullptr, dir.file("out/into.####.exr"), true));  // the default: the light only
    ASSERT_SF_OK(run(nullptr, dir.file("out/new.####.exr"), false));
    for (int64_t f = 1; f <= 4; ++f) {
        const ExrImage in = read_exr(frame("in", f)), into = read_exr(frame("into", f)), fresh = read_exr(frame("new", f));
        ASSERT_EQ(into.spec.channelnames, names);
        EXPECT_EQ(into.spec.format, OIIO::TypeDesc::FLOAT);
        EXPECT_EQ(part_count(frame("into", f)), 1);
        bool changed = false;
        for (int64_t p = 0; p < kW * kH; ++p)
            for (int64_t c = 0; c < 6; ++c) {
                const float v = into.pixels[p * 6 + c];
                if (c >= 3) {
                    ASSERT_EQ(v, in.pixels[p * 6 + c]) << "normal changed at frame " << f << " pixel " << p;
                } else {
                    // new files are half by default: compare the float copy at half's precision
                    EXPECT_NEAR(v, fresh.pixels[p * 3 + c], 2e-3f * std::abs(v) + 1e-6f);
                    changed = changed || v != in.pixels[p * 6 + c];
                }
            }
        EXPECT_TRUE(changed) << "frame " << f;
    }
}

TEST_F(IntoCopies, RefusedBeforeAnyWorkWhenItCannotBeDone) {
    sf_write_options tiled;
    sf_write_options_init(&tiled);
    tiled.tile_size = 16;
    EXPECT_EQ(run("ViewLayer.Diffuse Indirect", dir.file("out/t.####.exr"), true, &tiled), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(message.find("tiling"), std::string::npos) << message;
    EXPECT_EQ(run("ViewLayer.Diffuse Indirect", dir.file("out/t.####.tif"), true), SF_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(message.find(".exr"), std::string::npos) << message;
    EXPECT_FALSE(std::filesystem::exists(frame("t", 1)));
    // A sequence made in memory has no file to copy.
    Seq seq = create_sequence(shape_of(2, 4, 4, 3));
    ASSERT_TRUE(seq);
    sf_write_options w;
    sf_write_options_init(&w);
    w.into = 1;
    expect_failure(sf_sequence_write(seq.get(), dir.file("out/mem.####.exr").c_str(), &w), SF_ERROR_INVALID_ARGUMENT,
                   {"read from EXR files"});
}

// A sequence read from files can go back into copies from memory too.
TEST_F(IntoCopies, ASequenceReadFromFilesGoesBackFromMemory) {
    sf_read_options r;
    sf_read_options_init(&r);
    r.channels = "ViewLayer.Diffuse Indirect";
    sf_sequence raw = nullptr;
    ASSERT_SF_OK(sf_sequence_read(dir.file("in.####.exr").c_str(), &r, &raw));
    Seq seq(raw);
    sf_write_options w;
    sf_write_options_init(&w);
    w.into = 1;
    ASSERT_SF_OK(sf_sequence_write(seq.get(), dir.file("out/same.####.exr").c_str(), &w));
    for (int64_t f = 1; f <= 4; ++f)
        for (int part : {0, 1, 2}) EXPECT_EQ(read_exr(frame("in", f), part).pixels, read_exr(frame("same", f), part).pixels);
}
