// How a renderer's pass is told apart as files or as a layer of the input's own files, and that a
// layer needs an input read from files (pipeline/guide_sources.hpp). The layers' reading itself is
// tested end to end in tests/cli/test_pass_layers.py.
#include <gtest/gtest.h>

#include "pipeline/guide_sources.hpp"
#include "statfilter/error.hpp"
#include "statfilter/sequence.hpp"

using namespace statfilter;

TEST(PassNames, FilesHaveAFrameTokenADirectoryOrAnImageExtension) {
    for (const char* files : {"vector.####.exr", "vector.@@@@.exr", "vector.%04d.exr", "aux/vector", "vector.exr",
                              "VECTOR.EXR", "albedo.tif"})
        EXPECT_TRUE(pass_names_files(files)) << files;
    for (const char* layer : {"ViewLayer.Vector", "Vector", "ViewLayer.Denoising Albedo", "RenderLayer.Normal"})
        EXPECT_FALSE(pass_names_files(layer)) << layer;
}

TEST(PassNames, ALayerNeedsAnInputReadFromFiles) {
    Sequence in_memory(Shape{2, 4, 4, 3});
    try {
        pass_files("vectors", "ViewLayer.Vector", in_memory);
        FAIL() << "a layer of an input in memory was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("needs an input read from files"), std::string::npos) << e.what();
    }
    in_memory.source().pattern = "shot.####.exr";
    const PassFiles layer = pass_files("vectors", "ViewLayer.Vector", in_memory);
    EXPECT_EQ(layer.pattern, "shot.####.exr");
    EXPECT_EQ(layer.channels, "ViewLayer.Vector");
}
