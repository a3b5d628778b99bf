// statfilter report IN OUT [--ref REF] -o report.html: the review page. The page is built by the
// Python package (statfilter.report: NumPy, the plots), so this command starts Python on it, the
// way git runs its scripted subcommands; everything else of the CLI stays C++ over the C header.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
#include "cli_common.hpp"

namespace statfilter_cli {
namespace {

const char* const kBootstrap =
    "import sys\n"
    "try:\n"
    "    from statfilter.report import main\n"
    "except ImportError as e:\n"
    "    sys.stderr.write('statfilter report: the page is made by the statfilter Python package, which '\n"
    "                     'this Python cannot import (%s): install it with pip install . from the project '\n"
    "                     '(python/README.md), or set STATFILTER_PYTHON to a Python that has it\\n' % e)\n"
    "    sys.exit(1)\n"
    "sys.exit(main(sys.argv[1:], prog='statfilter report'))\n";

// In a build tree the package is staged beside the tools (build/python/statfilter): found first.
void add_staged_package_to_path() {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return;
    const std::filesystem::path staged = exe.parent_path().parent_path() / "python";
    if (!std::filesystem::exists(staged / "statfilter" / "report.py", ec)) return;
    const char* old = std::getenv("PYTHONPATH");
    const std::string path = staged.string() + (old && *old ? ":" + std::string(old) : "");
    ::setenv("PYTHONPATH", path.c_str(), 1);
}

}  // namespace

int cmd_report(int argc, char** argv) {
    const char* python = std::getenv("STATFILTER_PYTHON");
    if (!python || !*python) python = "python3";
    add_staged_package_to_path();
    std::vector<char*> args = {const_cast<char*>(python), const_cast<char*>("-c"), const_cast<char*>(kBootstrap)};
    for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
    args.push_back(nullptr);
    ::execvp(python, args.data());
    throw Failure(std::string("cannot start ") + python + " for the report: " + std::strerror(errno) +
                  " (set STATFILTER_PYTHON to a Python with the statfilter package)");
}

}  // namespace statfilter_cli
