// The file attributes of one frame (EXR header attributes: camera, frame, render statistics, ...),
// kept from reading and written back on output. Only the I/O layer and code that reads or sets
// attributes include this; the core's sequence type holds them without knowing what they are.
#pragma once
#include <OpenImageIO/paramlist.h>

namespace statfilter {

class FrameMetadata : public OIIO::ParamValueList {};

}  // namespace statfilter
