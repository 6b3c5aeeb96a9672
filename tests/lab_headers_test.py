#!/usr/bin/env python3
"""No lab sees its answers (labs/README.md): every translation unit under labs/ is compiled without the
folder of the lecture's finished shaders on its include path, and none of the headers it includes
holds a solution (raster/lecture/src/lecture/, solutions/). Nor does it parse the template pipeline
(pipeline_impl.hpp, the fill paths, the merge policies): labs draw through the teaching pipeline.

    lab_headers_test.py <build-dir> <source-dir>

Reads <build-dir>/compile_commands.json, reruns each lab's compile command with -MM (the headers it
includes, nothing compiled) and fails naming the lab and the header. Fails too if it finds no lab,
so that a build without labs cannot pass it by having nothing to check. The same for a submission's
compile in raster grade (<build-dir>/bin/grade_toolchain.json): none of its include folders holds an
answer or the grader's sources (raster/tools), since the grader lets a submission include whatever lies
beneath them.
"""
import json
import os
import shlex
import subprocess
import sys


def main(build_dir, source_dir):
    source_dir = os.path.realpath(source_dir)
    answers = [os.path.join(source_dir, "raster", "lecture", "src", "lecture"), os.path.join(source_dir, "solutions")]
    heavy = [("pipeline_impl.hpp",), ("fill", "fill_tile.hpp"), ("fastpath", "merge_policy.hpp")]
    with open(os.path.join(build_dir, "compile_commands.json")) as f:
        commands = json.load(f)
    labs_dir = os.path.join(source_dir, "labs") + os.sep
    labs = [c for c in commands if os.path.realpath(c["file"]).startswith(labs_dir)]
    if not labs:
        print("lab_headers_test: no lab translation unit in %s/compile_commands.json" % build_dir)
        return 1
    failed = toolchain_errors(build_dir, source_dir, answers)
    for entry in labs:
        lab = os.path.relpath(entry["file"], source_dir)
        args = shlex.split(entry["command"]) if "command" in entry else entry["arguments"]
        # The same command, asked only for its headers: -o <object> and -c dropped, -MM -MF - added.
        kept, skip = [], False
        for a in args:
            if skip:
                skip = False
                continue
            if a in ("-o", "-MF", "-MT", "-MQ"):
                skip = True
                continue
            if a in ("-c", "-MD", "-MMD"):
                continue
            kept.append(a)
        for a in kept:
            if a.startswith("-I"):
                include_dir = os.path.realpath(a[2:])
                if any(include_dir == d or include_dir.startswith(d + os.sep) for d in answers):
                    print("lab_headers_test: %s is compiled with %s on its include path" % (lab, a))
                    failed = 1
        out = subprocess.run(kept + ["-MM", "-MF", "-"], cwd=entry["directory"], capture_output=True, text=True)
        if out.returncode != 0:
            print("lab_headers_test: %s: the compiler failed:\n%s" % (lab, out.stderr))
            return 1
        headers = [h for h in out.stdout.replace("\\\n", " ").split()[1:] if h.endswith((".hpp", ".h"))]
        for h in headers:
            path = os.path.realpath(os.path.join(entry["directory"], h))
            if any(path.startswith(d + os.sep) for d in answers):
                print("lab_headers_test: %s includes %s, which holds a solution" % (lab, path))
                failed = 1
            # A lab draws through the library's teaching pipeline: parsing the template pipeline's
            # implementation would cost the lab loop its seconds and megabytes (labs/README.md).
            if any(path.endswith(os.path.join("raster", "pipeline", "include", "raster", *p)) for p in heavy):
                print("lab_headers_test: %s includes %s, the template pipeline (a lab draws through "
                      "raster/teaching_draw.hpp)" % (lab, path))
                failed = 1
        print("lab_headers_test: %s: %d headers, none holding a solution" % (lab, len(headers)))
    return failed


def toolchain_errors(build_dir, source_dir, answers):
    """1 if grade_toolchain.json puts an answer's folder, or raster/tools, on a submission's include path."""
    path = os.path.join(build_dir, "bin", "grade_toolchain.json")
    if not os.path.isfile(path):
        print("lab_headers_test: no %s (raster_tool writes it)" % path)
        return 1
    with open(path) as f:
        toolchain = json.load(f)
    include_dirs = [os.path.realpath(a[2:]) for a in toolchain["compile"] if a.startswith("-I") and len(a) > 2]
    if not include_dirs:
        print("lab_headers_test: %s names no include folder" % path)
        return 1
    forbidden = answers + [os.path.join(source_dir, "raster", "tools")]
    failed = 0
    for d in include_dirs:
        # A folder that holds one of them, or lies in one: a submission could #include it either way.
        if any(d == f or d.startswith(f + os.sep) or f.startswith(d + os.sep) for f in forbidden):
            print("lab_headers_test: grade_toolchain.json has -I%s, which holds or lies in one of %s" % (d, forbidden))
            failed = 1
    print("lab_headers_test: grade_toolchain.json's include folders: %s" % ", ".join(include_dirs))
    return failed


if __name__ == "__main__":
    if len(sys.argv) != 3:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2]))
