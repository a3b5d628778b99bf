// How a renderer's pass is told apart as files or as a layer of the input's own files (from the text
// alone), and that a layer needs an input read from files (pipeline/guide_sources.hpp). The layers' reading itself is
// tested end to end in tests/cli/test_pass_layers.py.
#include <gtest/gtest.h>

#include "pipeline/guide_sources.hpp"
#include "statfilter/error.hpp"
#include "statfilter/sequence.hpp"

using namespace statfilter;

TEST(PassNames, FilesHaveAFrameTokenADirectoryOrAnImageExtension) {
    for (const char* files : {"vector.####.exr", "vector.@@@@.exr", "vector.%04d.exr", "aux/vector", "aux\\vector",
                              "./vectors", "vector.exr", "VECTOR.EXR", "albedo.tif", "albedo.tga"})
        EXPECT_TRUE(pass_names_files(files)) << files;
    // The text alone decides: a layer's name stays one whatever the working directory holds.
    for (const char* layer : {"ViewLayer.Vector", "Vector", "vectors", "ViewLayer.Denoising Albedo", "RenderLayer.Normal"})
        EXPECT_FALSE(pass_names_files(layer)) << layer;
}

TEST(PassNames, ALayerNeedsAnInputReadFromFiles) {
    Sequence in_memory(Shape{2, 4, 4, 3});
    try {
        pass_files("vectors", "ViewLayer.Vector", in_memory);
        FAIL() << "a layer of an input in memory was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("not read from files"), std::string::npos) << e.what();
    }
}
