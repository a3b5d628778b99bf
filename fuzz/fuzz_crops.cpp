// Fuzz target: the crops.json reader (sf_crops_windows), which statfilter merge runs on a file the
// user gives. Any status is fine; a crash, a sanitizer report or a hang is a finding.
#include <cstdint>
#include <string>
#include <vector>

#include <statfilter/statfilter.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);  // NUL-terminated by c_str()
    size_t count = 0;
    int64_t width = 0, height = 0;
    if (sf_crops_windows(text.c_str(), nullptr, 0, &count, &width, &height) != SF_OK) return 0;
    // Every window was parsed from the text, so the count is bounded by its size.
    if (count > size) __builtin_trap();
    std::vector<sf_crop_window> windows(count + 1);
    size_t got = 0;
    if (sf_crops_windows(text.c_str(), windows.data(), count, &got, nullptr, nullptr) != SF_OK || got != count)
        __builtin_trap();
    for (size_t i = 0; i < got; ++i) {
        const sf_crop_window& w = windows[i];
        // The reader's promise to merge: every window lies inside the frame size it declares.
        if (w.x < 0 || w.y < 0 || w.width < 1 || w.height < 1 || w.x + w.width > width || w.y + w.height > height)
            __builtin_trap();
    }
    return 0;
}
