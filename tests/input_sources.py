#!/usr/bin/env python3
"""Where the executable reads its input from, checked on the executable (ctest label bad_input).

  input_sources.py EXE PRM_DIR WORK_DIR CHECK

CHECK is one of
  include   a parameter file that includes, from a subfolder, a file naming a Gmsh mesh by a
            relative path: the mesh is found next to the included file (the file that names it),
            from any working directory, with --validate and in a run; a mesh that is not there
            is refused with exit 1 and a message that prints the path it looked for and the file
            and line that named it.
  pipe      a parameter file read from a pipe (cat FILE | feticontact /dev/stdin), on one and on
            two MPI ranks: the same summary counts and displacements as the file itself.
  cgroup    under a memory cgroup limit of 600 MiB (v1 or v2; skipped, exit 77, where the test
            cannot create one), a scene whose memory estimate exceeds the limit but not the
            machine is refused by --validate with exit 1, a message that gives the limit's
            memory, and no process killed by the kernel.
Standard library only.
"""
import json
import os
import shutil
import subprocess
import sys

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []


def fail(text):
    print("FAILED:", text, flush=True)
    failures.append(text)


def run(cmd, cwd=None, stdin=None, timeout=300):
    print("$", " ".join(cmd), "(in %s)" % cwd if cwd else "", flush=True)
    return subprocess.run(cmd, cwd=cwd, stdin=stdin, capture_output=True, text=True,
                          timeout=timeout, env=ENV)


def include(exe, prm_dir, work):
    top = os.path.join(work, "include")
    shutil.rmtree(top, ignore_errors=True)
    os.makedirs(os.path.join(top, "bodies"))
    shutil.copy(os.path.join(prm_dir, "brick_k4.msh"), os.path.join(top, "bodies"))
    with open(os.path.join(top, "bodies", "brick.prm"), "w") as f:
        f.write("subsection Body 1\n  set Name = brick\n  subsection Mesh\n    set Type = gmsh\n"
                "    set File = brick_k4.msh\n  end\n  subsection Boundary conditions\n"
                "    set Clamped boundaries = 1\n    set Tractions = 6: 2e7, 0, -1e8\n  end\nend\n")
    with open(os.path.join(top, "scene.prm"), "w") as f:
        f.write("include bodies/brick.prm\nsubsection Output\n  set Directory = %s\nend\n"
                % os.path.join(top, "output"))
    for cwd in (top, work, "/"):
        p = run([exe, "--validate", os.path.join(top, "scene.prm")], cwd=cwd)
        if p.returncode != 0:
            fail("--validate from %s: exit %d: %s" % (cwd, p.returncode, p.stderr))
    p = run([exe, os.path.join(top, "scene.prm")], cwd="/")
    if p.returncode != 0 or not os.path.exists(os.path.join(top, "output", "summary.json")):
        fail("the run from /: exit %d: %s" % (p.returncode, p.stderr))
    # The mesh moved away: the message names where it looked and what named the file.
    os.rename(os.path.join(top, "bodies", "brick_k4.msh"), os.path.join(top, "brick_k4.msh"))
    p = run([exe, "--validate", os.path.join(top, "scene.prm")], cwd=top)
    looked = os.path.join(top, "bodies", "brick_k4.msh")
    if (p.returncode != 1 or looked not in p.stderr or
            os.path.join(top, "bodies", "brick.prm") not in p.stderr or "line 5" not in p.stderr):
        fail("a missing mesh: exit %d, stderr %r (expected the path %s, the file and line that "
             "named it)" % (p.returncode, p.stderr, looked))
    return 0


def summary_and_u(outdir):
    with open(os.path.join(outdir, "summary.json")) as f:
        s = json.load(f)
    with open(os.path.join(outdir, "displacements.csv")) as f:
        return s, f.read()


def pipe(exe, prm_dir, work):
    prm = os.path.join(prm_dir, "brick_contact.prm")
    base = os.path.join(work, "pipe")
    shutil.rmtree(base, ignore_errors=True)
    sets = ["--set", "Output/Write displacement csv=true", "--set", "Output/Write vtu=false"]
    p = run([exe, *sets, "--set", "Output/Directory=" + base + "/file", prm])
    if p.returncode != 0:
        fail("the run of the file: exit %d: %s" % (p.returncode, p.stderr))
        return 0
    want, want_u = summary_and_u(base + "/file")
    for np in (1, 2):
        outdir = "%s/pipe_np%d" % (base, np)
        cmd = [exe, *sets, "--set", "Output/Directory=" + outdir, "/dev/stdin"]
        if np > 1:
            cmd = ["mpirun", "--oversubscribe", "-np", str(np)] + cmd
        cat = subprocess.Popen(["cat", prm], stdout=subprocess.PIPE)
        p = run(cmd, stdin=cat.stdout)
        cat.wait()
        if p.returncode != 0:
            fail("a parameter file from a pipe on %d rank(s): exit %d: %s"
                 % (np, p.returncode, p.stderr))
            continue
        got, got_u = summary_and_u(outdir)
        for key in ("n_primal", "n_contact_nodes", "n_A", "iterations"):
            if got.get(key) != want.get(key):
                fail("from a pipe on %d rank(s): %s = %s, from the file %s"
                     % (np, key, got.get(key), want.get(key)))
        if got_u != want_u:
            fail("from a pipe on %d rank(s): other displacements than from the file" % np)
        with open(os.path.join(outdir, "input.prm")) as f, open(prm) as g:
            if f.read() != g.read():
                fail("from a pipe on %d rank(s): input.prm is not the file's text" % np)
    return 0


def memory_cgroup(limit_bytes):
    """A new memory cgroup limited to limit_bytes, as (folder, procs file), or None."""
    name = "feticontact_test_%d" % os.getpid()
    for root, limit_file in (("/sys/fs/cgroup/memory", "memory.limit_in_bytes"),
                             ("/sys/fs/cgroup", "memory.max"),
                             ("/sys/fs/cgroup/unified", "memory.max")):
        folder = os.path.join(root, name)
        try:
            os.mkdir(folder)
        except OSError:
            continue
        try:
            with open(os.path.join(folder, limit_file), "w") as f:
                f.write(str(limit_bytes))
            return folder
        except OSError:
            os.rmdir(folder)
    return None


def cgroup(exe, prm_dir, work):
    folder = memory_cgroup(600 * 1024 * 1024)
    if folder is None:
        print("no memory cgroup can be created here: skipped")
        return 77
    try:
        # A process must be able to join it (cgroup v2 refuses some placements).
        if subprocess.run(["sh", "-c", 'echo $$ > "%s/cgroup.procs"' % folder]).returncode != 0:
            print("no process can join the memory cgroup here: skipped")
            return 77
        prm = os.path.join(prm_dir, "brick_contact.prm")
        # About 780 MiB on one rank (doc/performance.md): above the limit, far below the machine.
        cmd = ["sh", "-c", 'echo $$ > "%s/cgroup.procs" && exec "$@"' % folder, "sh", exe,
               "--validate", "--set", "Body 1/Mesh/Subdivisions=72, 24, 24",
               "--set", "Output/Directory=" + os.path.join(work, "cgroup"), prm]
        p = run(cmd)
        if p.returncode != 1 or "MiB" not in p.stderr or "cgroup" not in p.stderr:
            fail("under a 600 MiB cgroup limit: exit %d (expected 1), stderr %r"
                 % (p.returncode, p.stderr))
    finally:
        os.rmdir(folder)
    return 0


def main():
    exe, prm_dir, work, check = sys.argv[1:5]
    os.makedirs(work, exist_ok=True)
    status = {"include": include, "pipe": pipe, "cgroup": cgroup}[check](exe, prm_dir, work)
    if failures:
        sys.exit("%d check(s) failed" % len(failures))
    sys.exit(status)


if __name__ == "__main__":
    main()
