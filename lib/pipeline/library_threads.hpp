// The thread pools of the libraries a run calls, held to the run's thread count while it runs (never
// raised above what they had), so that --threads N means N cores: OpenEXR's coder pool (through OpenImageIO's "exr_threads") and
// OpenBLAS's. Left alone, each sized itself to every core: `--quality fast --threads 1` decoded and
// compressed its frames and multiplied its matrices on 1.4-1.6 cores. OpenCV's pool is left as it
// is: its TBB back end cannot be shrunk and grown again without warnings on stderr, and statfilter
// calls it inside its own threads, where it adds little (balanced on one thread: 1.01 cores on
// average, 1.18 at most, in its motion compensation).
//
// These pools are process-wide, and resizing one while another thread is inside it is not safe, so
// they are set only by the first of overlapping runs (in any thread) and put back as they were found
// when the last one ends; a run that starts while another is running uses the pools as they are.
#pragma once

namespace statfilter {

class LibraryThreads {
public:
    explicit LibraryThreads(int threads);
    ~LibraryThreads();
    LibraryThreads(const LibraryThreads&) = delete;
    LibraryThreads& operator=(const LibraryThreads&) = delete;
};

}  // namespace statfilter
