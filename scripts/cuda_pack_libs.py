#!/usr/bin/env python3
"""Gathers the shared libraries that the programs in BIN load into LIB, for
scripts/cuda_pack.sh, within the size a GPU machine's upload allows.

OpenCV's image and video readers pull in GDAL, FFmpeg, GStreamer, GDCM
and their own dependencies: several hundred MB that no CUDA check calls
(the checks read and write PNG, which stays real, as does OpenEXR, whose
codec OpenCV sets up on its first image). Each of those
libraries is replaced by a stub with its name and symbol versions that
defines every symbol the packed code imports from it, as a function that
returns 0 (OpenCV's GDAL codec calls GDALAllRegister when it is set up;
nothing else is called). The loader binds symbols at load time (OpenCV is
linked with BIND_NOW), so the stub must define them all.

    scripts/cuda_pack_libs.py BIN LIB
"""
import os
import re
import subprocess
import sys
import tempfile

# The C library, the C++ runtime and the CUDA driver: the GPU machine's own.
SYSTEM = re.compile(r"^(linux-vdso|ld-linux|libc|libm|libdl|libpthread|librt|"
                    r"libstdc\+\+|libgcc_s|libcuda)[.-]")
# Readers no check uses, and what only they load.
STUBBED = re.compile(r"^(libgdal|libgdcm|libavcodec|libavformat|"
                     r"libavutil|libswscale|libswresample|libgst|libgobject|"
                     r"libglib|libdc1394|libgphoto2|libraw1394)")
DYNSYM = re.compile(r"^[0-9a-f]+ (.{7}) (\S+)\s+([0-9a-f]+)\s+"
                    r"(?:\(?([A-Za-z_][\w.@]*)\)?\s+)?(\S+)$")


def run(*args):
    done = subprocess.run(args, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("cuda_pack_libs.py: %s failed:\n%s" % (" ".join(args),
                                                       done.stderr[-2000:]))
    return done.stdout


def resolved(path):
    """{soname: file} of every library `path` loads, as ldd finds them."""
    libs = {}
    for line in run("ldd", path).splitlines():
        parts = line.split()
        if len(parts) >= 3 and parts[1] == "=>" and parts[2].startswith("/"):
            libs[parts[0]] = parts[2]
    return libs


def needed(path):
    return re.findall(r"\(NEEDED\)\s+Shared library: \[(.+)\]",
                      run("readelf", "-d", path))


def dynamic_symbols(path):
    """[(name, version, is_function, size, defined)] of `path`'s table."""
    symbols = []
    for line in run("objdump", "-T", path).splitlines():
        m = DYNSYM.match(line)
        if not m:
            continue
        flags, section, size, version, name = m.groups()
        symbols.append((name, version if version and
                        version != "Base" else None,
                        "F" in flags, int(size, 16), section != "*UND*"))
    return symbols


def imported(paths):
    """{(name, version)} of the symbols `paths` take from elsewhere."""
    return {(name, version) for path in paths
            for name, version, _, _, defined in dynamic_symbols(path)
            if not defined}


def write_stub(soname, path, wanted, lib_dir, work):
    """Writes lib_dir/soname: `path`'s symbols among `wanted`."""
    source, nodes = [], {}
    for name, version, function, size, defined in dynamic_symbols(path):
        if not defined or (name, version) not in wanted and \
                (name, None) not in wanted:
            continue
        if (name, version) in nodes.get(version, ()):
            continue
        nodes.setdefault(version, set()).add((name, version))
        c_name = "stub_%d" % len(source)
        if function:
            source.append('long %s(void) __asm__("%s");\n'
                          'long %s(void) { return 0; }\n' % (c_name, name,
                                                            c_name))
        else:
            source.append('char %s[%d] __asm__("%s");\n' % (c_name,
                                                           max(size, 1),
                                                           name))
    c_file = os.path.join(work, soname + ".c")
    with open(c_file, "w") as f:
        f.write("".join(source))
    # Versioned symbols need their version nodes; the rest stay unversioned.
    map_file = os.path.join(work, soname + ".map")
    with open(map_file, "w") as f:
        for version, names in sorted(nodes.items(), key=lambda kv: str(kv[0])):
            if version:
                f.write("%s { global: %s };\n" %
                        (version, "".join("%s;" % n for n, _ in sorted(names))))
    versioned = ["-Wl,--version-script=" + map_file] if any(nodes) else []
    run("gcc", "-shared", "-fPIC", "-o", os.path.join(lib_dir, soname),
        "-Wl,-soname," + soname, *versioned, c_file)


def main(bin_dir, lib_dir):
    programs = [os.path.join(bin_dir, p) for p in sorted(os.listdir(bin_dir))]
    where = {}
    for program in programs:
        where.update(resolved(program))
    # The libraries loaded, walking NEEDED entries but not into stubs.
    real, stubs, todo = {}, {}, list(programs)
    while todo:
        for soname in needed(todo.pop()):
            if SYSTEM.match(soname) or soname in real or soname in stubs:
                continue
            if soname not in where:
                sys.exit("cuda_pack_libs.py: %s not found by ldd" % soname)
            if STUBBED.match(soname):
                stubs[soname] = where[soname]
            else:
                real[soname] = where[soname]
                todo.append(where[soname])
    os.makedirs(lib_dir, exist_ok=True)
    for soname, path in real.items():
        with open(path, "rb") as src, \
                open(os.path.join(lib_dir, soname), "wb") as dst:
            dst.write(src.read())
    wanted = imported(programs + list(real.values()))
    with tempfile.TemporaryDirectory() as work:
        for soname, path in stubs.items():
            write_stub(soname, path, wanted, lib_dir, work)
    print("cuda_pack_libs.py: %d libraries, %d stubs (%s)" %
          (len(real), len(stubs), " ".join(sorted(stubs))))


if __name__ == "__main__":
    if len(sys.argv) == 2 and sys.argv[1] in ("-h", "--help"):
        print(__doc__)
    elif len(sys.argv) != 3:
        sys.exit(__doc__)
    else:
        main(sys.argv[1], sys.argv[2])
