"""Where the package looks for Intel OIDN: an installed pyoidn only, never a folder in the working
directory (whoever controls the working directory must not choose the library that is loaded)."""

import os
import subprocess
import sys


def oidn_library_seen_from(cwd):
    env = {k: v for k, v in os.environ.items() if k != "STATFILTER_OIDN_LIBRARY"}
    proc = subprocess.run([sys.executable, "-c", "import os, statfilter; print(os.environ.get('STATFILTER_OIDN_LIBRARY'))"],
                          cwd=cwd, env=env, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.strip()


def test_a_pyoidn_folder_in_the_working_directory_is_not_taken(tmp_path):
    planted = tmp_path / "pyoidn"
    (planted / "oidn" / "lib").mkdir(parents=True)
    (planted / "__init__.py").write_text("raise SystemExit('the planted pyoidn was imported')\n")
    (planted / "oidn" / "lib" / "libOpenImageDenoise.so.2").write_bytes(b"not a library")
    seen = oidn_library_seen_from(tmp_path)
    assert str(tmp_path) not in seen
    assert seen == "None" or "site-packages" in seen or "dist-packages" in seen, seen
