"""The ctypes bindings against the C header: every sf_ function declared with the right argtypes and
restype, every struct mirrored member by member, enums and callbacks matching."""

import ctypes
import os
import re
import shutil
import subprocess

import pytest

from conftest import HEADER
from statfilter import _capi
import statfilter


def _raw_header_text(path=HEADER, seen=None):
    """statfilter.h with the headers of its own directory that it includes ("x.h") in place, each once."""
    seen = set() if seen is None else seen
    seen.add(os.path.basename(path))
    with open(path, encoding="utf-8") as f:
        text = f.read()

    def include(m):
        name = m.group(1)
        return "" if name in seen else _raw_header_text(os.path.join(os.path.dirname(path), name), seen)
    return re.sub(r'^#include "([\w.]+)"[^\n]*$', include, text, flags=re.M)


def _header_text():
    text = _raw_header_text()
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    # Drop preprocessor lines (the SF_API definition itself).
    return "\n".join(line for line in text.splitlines() if not line.lstrip().startswith("#"))


def _norm(c_type):
    c_type = re.sub(r"\bconst\b", " ", c_type)
    c_type = re.sub(r"\s*\*\s*", "*", c_type)
    return " ".join(c_type.split()).replace(" *", "*")


def _split_decl(decl):
    """'const char* name' -> ('char*', 'name')."""
    decl = " ".join(decl.split())
    m = re.match(r"^(.*?)(\w+)$", decl)
    assert m, "cannot parse declaration %r" % decl
    return _norm(m.group(1)), m.group(2)


HEADER_TEXT = _header_text()


def header_functions():
    """{name: (return type, [parameter types])} for every SF_API function."""
    out = {}
    for m in re.finditer(r"\bSF_API\s+([^;{}()]*?)\b(sf_\w+)\s*\(([^)]*)\)\s*;", HEADER_TEXT):
        ret, name, params = _norm(m.group(1)), m.group(2), m.group(3).strip()
        types = [] if params in ("", "void") else [_split_decl(p)[0] for p in params.split(",")]
        out[name] = (ret, types)
    return out


def header_structs():
    out = {}
    for m in re.finditer(r"typedef\s+struct\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", HEADER_TEXT, flags=re.S):
        members = [_split_decl(d) for d in m.group(2).split(";") if d.strip()]
        out[m.group(3)] = members
    return out


def header_enums():
    out = {}
    for m in re.finditer(r"typedef\s+enum\s+(\w+)\s*\{(.*?)\}\s*(\w+)\s*;", HEADER_TEXT, flags=re.S):
        values = {}
        for item in m.group(2).split(","):
            if item.strip():
                k, v = item.split("=")
                values[k.strip()] = int(v.strip())
        out[m.group(3)] = values
    return out


def header_callbacks():
    out = {}
    for m in re.finditer(r"typedef\s+([\w\s\*]+?)\s*\(\s*\*\s*(\w+)\s*\)\s*\(([^)]*)\)\s*;", HEADER_TEXT):
        params = m.group(3).strip()
        out[m.group(2)] = (_norm(m.group(1)), [] if params in ("", "void") else [_split_decl(p)[0] for p in params.split(",")])
    return out


def expected_ctype(c_type):
    """The ctypes type a C type must be bound as."""
    base = {
        "void": None, "int": ctypes.c_int, "double": ctypes.c_double, "float": ctypes.c_float,
        "int64_t": ctypes.c_int64, "size_t": ctypes.c_size_t, "unsigned": ctypes.c_uint,
        "sf_sequence": _capi.sf_sequence, "sf_filter": _capi.sf_filter,
        "sf_progress_callback": _capi.sf_progress_callback, "sf_error_callback": _capi.sf_error_callback,
        "char*": ctypes.c_char_p, "void*": ctypes.c_void_p,
    }
    for enum in header_enums():
        base[enum] = ctypes.c_int
    for callback in header_callbacks():  # function-pointer typedefs (the plugin struct's members)
        base[callback] = getattr(_capi, callback)
    if c_type in base:
        return base[c_type]
    if c_type in _capi.STRUCTS:
        return _capi.STRUCTS[c_type]
    if c_type.endswith("*"):
        inner = expected_ctype(c_type[:-1])
        assert inner is not None, c_type
        return ctypes.POINTER(inner)
    raise AssertionError("the test does not know the C type %r: extend expected_ctype" % c_type)


def test_header_parses():
    functions = header_functions()
    # The parser must see the header's API, not silently nothing.
    assert len(functions) >= 40
    for name in ("sf_version", "sf_sequence_wrap", "sf_filter_execute", "sf_sequence_read"):
        assert name in functions
    assert functions["sf_sequence_wrap"] == ("sf_status", ["float*", "sf_shape", "sf_strides", "sf_sequence*"])
    assert functions["sf_filter_get_string"] == ("sf_status", ["sf_filter", "char*", "char**"])
    assert {"sf_shape", "sf_strides", "sf_read_options", "sf_write_options", "sf_param_info"} <= set(header_structs())


def test_every_header_struct_is_mirrored():
    assert set(header_structs()) == set(_capi.STRUCTS)


def test_every_header_function_is_bound():
    functions = header_functions()
    missing = sorted(set(functions) - set(_capi.FUNCTIONS))
    assert not missing, "functions in statfilter.h without argtypes/restype in _capi.FUNCTIONS: %s" % missing
    stale = sorted(set(_capi.FUNCTIONS) - set(functions))
    assert not stale, "bindings for functions not in statfilter.h: %s" % stale


def test_library_exports_every_function():
    assert _capi.MISSING == [], "%s lacks %s" % (_capi.library_path, _capi.MISSING)


@pytest.mark.parametrize("name", sorted(header_functions()))
def test_function_signature(name):
    ret, params = header_functions()[name]
    fn = getattr(_capi.lib, name)
    assert fn.argtypes is not None, "%s has no argtypes" % name
    assert list(fn.argtypes) == [expected_ctype(t) for t in params], name
    assert fn.restype is expected_ctype(ret), "%s returns %s, bound as %r" % (name, ret, fn.restype)


@pytest.mark.parametrize("struct", sorted(_capi.STRUCTS))
def test_struct_members(struct):
    members = header_structs()[struct]
    fields = _capi.STRUCTS[struct]._fields_
    assert [n for n, _ in fields] == [n for _, n in members], struct
    for (name, ctype), (c_type, _) in zip(fields, members):
        assert ctype is expected_ctype(c_type), "%s.%s is %s in C, %r in Python" % (struct, name, c_type, ctype)


def test_enums_match():
    enums = header_enums()
    assert set(enums) == {"sf_status", "sf_pixel_type", "sf_param_type", "sf_filter_kind"}
    for values in enums.values():
        for key, value in values.items():
            assert getattr(_capi, key) == value, key
    # One exception class per error status.
    from statfilter import errors
    codes = {v for k, v in enums["sf_status"].items() if k != "SF_OK"}
    assert set(errors.ERRORS) == codes
    for code, cls in errors.ERRORS.items():
        assert issubclass(cls, statfilter.Error)
        assert cls.status == code
        assert statfilter.Error("x", code).status_name == [k for k, v in enums["sf_status"].items() if v == code][0]


def test_callbacks_match():
    callbacks = header_callbacks()
    assert set(callbacks) == {"sf_progress_callback", "sf_error_callback", "sf_plugin_probe_fn", "sf_plugin_create_fn",
                              "sf_plugin_set_param_fn", "sf_plugin_execute_fn", "sf_plugin_execute_frame_fn",
                              "sf_plugin_release_fn", "sf_plugin_entry_fn"}
    for name, (ret, params) in callbacks.items():
        py = getattr(_capi, name)
        assert py._restype_ is expected_ctype(ret), name
        assert list(py._argtypes_) == [expected_ctype(t) for t in params], name


def test_plugin_constants_match_header():
    define = dict(re.findall(r"#define\s+(SF_PLUGIN_\w+)\s+(\S+)", _raw_header_text()))
    assert int(define["SF_PLUGIN_ABI_VERSION"]) == _capi.SF_PLUGIN_ABI_VERSION
    assert int(define["SF_PLUGIN_ABI_VERSION_FIRST"]) == _capi.SF_PLUGIN_ABI_VERSION_FIRST
    assert int(define["SF_PLUGIN_THREAD_SAFE"].rstrip("u")) == _capi.SF_PLUGIN_THREAD_SAFE
    assert define["SF_PLUGIN_ENTRY"].strip('"') == _capi.SF_PLUGIN_ENTRY


def test_version_matches_header():
    with open(HEADER, encoding="utf-8") as f:
        define = dict(re.findall(r"#define\s+(SF_VERSION_\w+)\s+(\d+)", f.read()))
    text = "%s.%s.%s" % (define["SF_VERSION_MAJOR"], define["SF_VERSION_MINOR"], define["SF_VERSION_PATCH"])
    assert statfilter.version() == text
    assert _capi.lib.sf_version() == (int(define["SF_VERSION_MAJOR"]) * 10000 + int(define["SF_VERSION_MINOR"]) * 100
                                      + int(define["SF_VERSION_PATCH"]))


def test_struct_layout_matches_c_compiler(tmp_path):
    """sizeof and offsetof of every struct member, from a C compiler, equal ctypes' layout."""
    cc = shutil.which(os.environ.get("CC", "cc")) or shutil.which("gcc") or shutil.which("clang")
    if not cc:
        pytest.skip("no C compiler to check struct layouts")
    lines = ["#include <stdio.h>", "#include <stddef.h>", "#include \"statfilter/statfilter.h\"", "int main(void) {"]
    for struct, members in header_structs().items():
        lines.append('printf("%s %%zu\\n", sizeof(%s));' % (struct, struct))
        for _, member in members:
            lines.append('printf("%s.%s %%zu\\n", offsetof(%s, %s));' % (struct, member, struct, member))
    lines += ["return 0;", "}"]
    src = tmp_path / "layout.c"
    src.write_text("\n".join(lines))
    exe = tmp_path / "layout"
    include = os.path.dirname(os.path.dirname(HEADER))
    subprocess.run([cc, "-std=c99", "-I", include, str(src), "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout
    c_layout = dict(line.split() for line in out.splitlines())
    for struct, members in header_structs().items():
        cls = _capi.STRUCTS[struct]
        assert ctypes.sizeof(cls) == int(c_layout[struct]), struct
        for _, member in members:
            assert getattr(cls, member).offset == int(c_layout["%s.%s" % (struct, member)]), (struct, member)


def test_error_check_uses_c_message():
    handle = _capi.sf_sequence()
    status = _capi.lib.sf_sequence_create(_capi.sf_shape(0, 1, 1, 1), ctypes.byref(handle))
    with pytest.raises(statfilter.InvalidArgumentError) as info:
        statfilter.errors.check(status)
    assert info.value.status == _capi.SF_ERROR_INVALID_ARGUMENT
    assert "dimension" in info.value.message
    assert isinstance(info.value, ValueError)
    assert not handle


def test_owned_sequence_and_copy_to(rng):
    """sf_sequence_create / sf_sequence_data / sf_sequence_copy_to / channel stats through the bindings."""
    import numpy as np
    handle = _capi.sf_sequence()
    statfilter.errors.check(_capi.lib.sf_sequence_create(_capi.sf_shape(2, 3, 4, 2), ctypes.byref(handle)))
    try:
        data = ctypes.POINTER(ctypes.c_float)()
        strides = _capi.sf_strides()
        statfilter.errors.check(_capi.lib.sf_sequence_data(handle, ctypes.byref(data), ctypes.byref(strides)))
        assert (strides.channel, strides.pixel, strides.row, strides.frame) == (4, 8, 32, 96)
        values = rng.random(48).astype(np.float32)
        ctypes.memmove(data, values.ctypes.data, values.nbytes)
        dst = np.zeros((2, 3, 4, 2), np.float32)
        statfilter.errors.check(_capi.lib.sf_sequence_copy_to(
            handle, dst.ctypes.data_as(ctypes.POINTER(ctypes.c_float)),
            _capi.sf_strides(channel=4, pixel=8, row=32, frame=96)))
        np.testing.assert_array_equal(dst.reshape(-1), values)
        stats = _capi.sf_channel_stats()
        statfilter.errors.check(_capi.lib.sf_sequence_channel_stats(handle, 1, ctypes.byref(stats)))
        ch = values.reshape(2, 3, 4, 2)[..., 1]
        assert stats.min == pytest.approx(ch.min()) and stats.max == pytest.approx(ch.max())
        assert stats.mean == pytest.approx(ch.mean(), rel=1e-6)
        assert stats.nan_count == 0 and stats.inf_count == 0
        name = ctypes.c_char_p()
        statfilter.errors.check(_capi.lib.sf_sequence_channel_name(handle, 1, ctypes.byref(name)))
        assert name.value == b"C1"
    finally:
        statfilter.errors.check(_capi.lib.sf_sequence_release(handle))


def test_library_found():
    assert os.path.exists(statfilter.library_path) or "/" not in statfilter.library_path


def test_library_search_error_lists_places(monkeypatch, tmp_path):
    from statfilter import _library
    monkeypatch.setattr(_library, "_PACKAGE_DIR", str(tmp_path))
    monkeypatch.setenv(_library.ENV_VAR, str(tmp_path / "nowhere.so"))
    monkeypatch.setattr(_library.ctypes.util, "find_library", lambda name: None)
    with pytest.raises(ImportError) as info:
        _library.load_library()
    message = str(info.value)
    assert str(tmp_path / "libstatfilter.so.0") in message
    assert str(tmp_path / "nowhere.so") in message
    assert "find_library" in message


def test_library_from_environment(monkeypatch, tmp_path):
    from statfilter import _library
    monkeypatch.setattr(_library, "_PACKAGE_DIR", str(tmp_path))
    monkeypatch.setenv(_library.ENV_VAR, _capi.library_path)
    lib, path = _library.load_library()
    assert path == _capi.library_path
    lib.sf_version_string.restype = ctypes.c_char_p
    assert lib.sf_version_string().decode() == statfilter.version()


def test_missing_system_library_names_the_debian_package():
    from statfilter import _library
    error = "libOpenColorIO.so.2.1: cannot open shared object file: No such file or directory"
    message = _library.missing_system_library_message("/x/statfilter/libstatfilter.so.0", error)
    assert "libOpenColorIO.so.2.1" in message and "libopencolorio2.1" in message
    assert "apt-get install" in message and "libopenimageio2.4" in message
    # Other failures keep the search report.
    assert _library.missing_system_library_message("/x/libstatfilter.so.0", "invalid ELF header") is None
    assert _library.missing_system_library_message(
        "/x/a.so", "libstatfilter.so.0: cannot open shared object file: No such file or directory") is None


def test_missing_system_library_raises_import_error(monkeypatch, tmp_path):
    from statfilter import _library
    (tmp_path / "libstatfilter.so.0").write_bytes(b"")

    def cdll(path):
        raise OSError("liblapacke.so.3: cannot open shared object file: No such file or directory")
    monkeypatch.setattr(_library, "_PACKAGE_DIR", str(tmp_path))
    monkeypatch.setattr(_library.ctypes, "CDLL", cdll)
    with pytest.raises(ImportError, match="liblapacke.so.3.*not installed"):
        _library.load_library()


def test_every_system_library_the_library_links_is_listed():
    """The table behind the import-time message matches what the loaded library really links."""
    readelf = shutil.which("readelf")
    if not readelf:
        pytest.skip("no readelf")
    from statfilter import _library
    out = subprocess.run([readelf, "-d", statfilter.library_path], capture_output=True, text=True, check=True).stdout
    needed = {line.split("[")[1].rstrip("]") for line in out.splitlines() if "(NEEDED)" in line}
    runtime = {"libstdc++.so.6", "libm.so.6", "libgcc_s.so.1", "libc.so.6", "ld-linux-x86-64.so.2"}
    if any(re.match(r"lib(a|ub|t|l)san\.so", n) for n in needed):
        pytest.skip("a sanitizer build links more libraries (no --as-needed) than the wheel's Release build")
    assert needed - runtime == set(_library.SYSTEM_LIBRARIES), needed


def test_public_api_is_typed():
    import inspect
    package = os.path.dirname(statfilter.__file__)
    assert os.path.exists(os.path.join(package, "py.typed"))
    for name in statfilter.__all__:
        obj = getattr(statfilter, name)
        functions = [obj] if inspect.isfunction(obj) else \
            [f for k, f in vars(obj).items() if inspect.isfunction(f) and (not k.startswith("_") or k in
             ("__init__", "__call__"))] if inspect.isclass(obj) else []
        for f in functions:
            sig = inspect.signature(f)
            untyped = [p for p in sig.parameters.values()
                       if p.name not in ("self", "cls") and p.annotation is inspect.Parameter.empty]
            assert not untyped, "%s.%s: %s" % (name, f.__name__, untyped)
            assert sig.return_annotation is not inspect.Signature.empty, "%s.%s returns no type" % (name, f.__name__)
