#!/usr/bin/env python3
"""Output integrity and a clean output directory, checked on the executable (ctest label
bad_input).

  output_integrity.py EXE PRM_DIR WORK_DIR CHECK [--np N]

CHECK is one of
  full-device  the scene on a small tmpfs of many sizes (the test mounts them; it is skipped,
               exit 77, where it may not): every run either succeeds with every result file
               complete, or exits 1 naming a file and "No space left on device" and leaves no
               file that looks like a result (no summary.json, VTU, PVD, CSV, HDF5, tables);
               never a signal or exit 3.
  clean        a good run, then one that stops on bad input, then a plain one after an FCLIB
               export (if the build has FCLIB) and after a refinement study: each run's folder
               holds no file of the earlier run, and a file of the user's stays; then runs of
               the earlier run's input.prm and parameters.prm in that folder, which stay.
  killed       a run killed (SIGKILL) in the middle of its solve leaves no file that looks
               complete; the next run removes what it left.
  unwritable   an output directory that cannot be created or written, or that holds a folder
               with the name of a result file: exit 1, the message names the directory (or the
               folder) and the reason.
  locked       an output directory in use: a run into a folder whose lock file another process
               holds exits 1 naming that process and leaves the folder as it was; --validate
               is not refused; two real runs started into one folder, the second while the first
               solves: the second exits 1 and the first's files are complete and its own; a lock
               file left by a dead process is taken over with a warning; no lock file remains
               after a run.
Standard library only.
"""
import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import time

RESULTS = (".json", ".vtu", ".pvtu", ".pvd", ".csv", ".hdf5", ".txt", ".org")
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []


def fail(text):
    print("FAILED:", text, flush=True)
    failures.append(text)


def command(exe, prm, outdir, sets=(), np=1):
    cmd = [exe, "--set", "Output/Directory=" + outdir]
    for s in sets:
        cmd += ["--set", s]
    cmd.append(prm)
    if np > 1:
        cmd = ["mpirun", "--oversubscribe", "-np", str(np)] + cmd
    return cmd


def run(exe, prm, outdir, sets=(), np=1, timeout=300):
    cmd = command(exe, prm, outdir, sets, np)
    print("$", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=ENV)
    return p


def looks_like_results(outdir):
    """Files and folders in outdir that look like a result of a run (log.txt and the input
    files excepted)."""
    if not os.path.isdir(outdir):
        return []
    found = []
    for name in sorted(os.listdir(outdir)):
        if name == "log.txt":
            continue
        if name.endswith(RESULTS) or name.startswith("cycle-"):
            found.append(name)
    return found


COMPLETE = ["summary.json", "contact.csv", "history.csv", "solution.pvd", "solution.pvtu",
            "contact_surface.pvtu", "contact_surface.pvd"]


def check_complete(outdir, what):
    names = set(os.listdir(outdir))
    for name in COMPLETE:
        if name not in names:
            fail("%s: exit 0 but %s is missing" % (what, name))
    leftovers = [n for n in names if n.endswith(".partial")]
    if leftovers:
        fail("%s: exit 0 and temporary files left: %s" % (what, leftovers))
    with open(os.path.join(outdir, "summary.json")) as f:
        text = f.read()
    if not text.rstrip().endswith("}"):
        fail("%s: summary.json is incomplete" % what)


def full_device(exe, prm_dir, work, np):
    mount = os.path.join(work, "tmpfs")
    os.makedirs(mount, exist_ok=True)
    probe = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", mount],
                           capture_output=True)
    if probe.returncode != 0:
        print("cannot mount a tmpfs here: skipped")
        return 77
    subprocess.run(["umount", mount])
    prm = os.path.join(prm_dir, "brick_contact.prm")
    sizes = [4, 12, 24, 32, 48, 64, 80, 100, 128, 160, 200, 220, 240, 320, 1024]
    n_failed_writes = n_complete = 0
    try:
        for kib in sizes:
            subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%dk" % kib, "tmpfs", mount],
                           check=True)
            outdir = os.path.join(mount, "out")
            what = "tmpfs of %d KiB, %d rank(s)" % (kib, np)
            p = run(exe, prm, outdir, ["Output/Write displacement csv=true"], np)
            if p.returncode < 0 or p.returncode not in (0, 1):
                fail("%s: exit status %d\n%s" % (what, p.returncode, p.stderr[-2000:]))
            elif p.returncode == 1:
                n_failed_writes += 1
                if "No space left on device" not in p.stderr or "output file <" not in p.stderr:
                    fail("%s: the message names no file or no reason: %s" % (what, p.stderr))
                left = looks_like_results(outdir)
                if left:
                    fail("%s: exit 1 but files that look like results: %s" % (what, left))
            else:
                n_complete += 1
                check_complete(outdir, what)
            print("  %s: exit %d" % (what, p.returncode), flush=True)
            subprocess.run(["umount", mount], check=True)
    finally:
        subprocess.run(["umount", mount], capture_output=True)
    if n_failed_writes < 5 or n_complete < 1:
        fail("the sizes did not cover both outcomes: %d failed, %d complete"
             % (n_failed_writes, n_complete))
    return 0


def clean(exe, prm_dir, work, fclib):
    outdir = os.path.join(work, "clean")
    shutil.rmtree(outdir, ignore_errors=True)
    os.makedirs(outdir)
    with open(os.path.join(outdir, "notes of the user.txt"), "w") as f:
        f.write("not written by feticontact\n")
    contact = os.path.join(prm_dir, "brick_contact.prm")
    hertz = os.path.join(prm_dir, "hertz.prm")

    p = run(exe, contact, outdir)
    if p.returncode != 0:
        fail("the good run failed: %s" % p.stderr)
    check_complete(outdir, "good run")

    # Bad input found while parsing, and found while building the scene.
    for sets, what in ((["Body 1/Material/Young's modulus=0"], "bad value"),
                       (["Body 1/Mesh/Type=gmsh", "Body 1/Mesh/File=no_such.msh"], "no mesh")):
        p = run(exe, contact, outdir, sets)
        if p.returncode != 1:
            fail("%s: exit %d, expected 1" % (what, p.returncode))
        left = [n for n in os.listdir(outdir) if n != "notes of the user.txt"]
        if left:
            fail("%s: files of the earlier run left: %s" % (what, left))

    if fclib:
        p = run(exe, contact, outdir, ["Output/Write FCLIB problem=true"])
        if p.returncode != 0 or not os.path.exists(os.path.join(outdir, "fclib_problem.hdf5")):
            fail("the FCLIB export failed: %s" % p.stderr)
        p = run(exe, contact, outdir)
        if os.path.exists(os.path.join(outdir, "fclib_problem.hdf5")):
            fail("a plain run after an FCLIB export left fclib_problem.hdf5")

    p = run(exe, hertz, outdir, ["Refinement study/Subdivision factors=0.5, 0.6"])
    if p.returncode != 0 or not os.path.isdir(os.path.join(outdir, "cycle-2")):
        fail("the refinement study failed: %s" % p.stderr[-2000:])
    p = run(exe, contact, outdir)
    for name in ("cycle-1", "cycle-2", "convergence_table.txt", "convergence_table.org",
                 "refinement_study.json"):
        if os.path.exists(os.path.join(outdir, name)):
            fail("a plain run after a refinement study left %s" % name)
    if not os.path.exists(os.path.join(outdir, "notes of the user.txt")):
        fail("the user's own file was removed")
    check_complete(outdir, "plain run after the refinement study")

    # A run of the earlier run's own input, in its folder: the input is read, not removed.
    for name in ("input.prm", "parameters.prm"):
        prm = os.path.join(outdir, name)
        p = run(exe, prm, outdir)
        if p.returncode != 0:
            fail("a run of the earlier run's %s: exit %d: %s" % (name, p.returncode, p.stderr))
        elif not os.path.exists(prm):
            fail("a run of the earlier run's %s removed it" % name)
        else:
            check_complete(outdir, "run of the earlier run's " + name)
    return 0


def killed(exe, prm_dir, work):
    outdir = os.path.join(work, "killed")
    shutil.rmtree(outdir, ignore_errors=True)
    prm = os.path.join(prm_dir, "brick_contact.prm")
    # Large enough that its solve lasts well beyond the second after which it is killed.
    cmd = command(exe, prm, outdir, ["Body 1/Mesh/Subdivisions=60, 20, 20"])
    print("$", " ".join(cmd), "(killed 1 s into its solve)", flush=True)
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=ENV)
    log = os.path.join(outdir, "log.txt")
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        if os.path.exists(log) and "FETI:" in open(log, errors="replace").read():
            time.sleep(1)
            break
        time.sleep(0.05)
    if proc.poll() is not None:
        fail("the run ended (exit %d) before it could be killed" % proc.returncode)
        return 0
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    left = looks_like_results(outdir)
    if left:
        fail("a killed run left files that look complete: %s" % left)
    p = run(exe, prm, outdir)
    if p.returncode != 0:
        fail("the run after the killed one failed: %s" % p.stderr)
    leftovers = [n for n in os.listdir(outdir) if n.endswith(".partial")]
    if leftovers:
        fail("the next run did not remove the killed run's temporary files: %s" % leftovers)
    return 0


def unwritable(exe, prm_dir, work):
    prm = os.path.join(prm_dir, "brick_contact.prm")
    blocker = os.path.join(work, "a regular file")
    with open(blocker, "w") as f:
        f.write("x\n")
    for outdir in (os.path.join(blocker, "out"), "/proc/feticontact_out"):
        p = run(exe, prm, outdir)
        if p.returncode != 1:
            fail("output directory %s: exit %d, expected 1 (%s)" % (outdir, p.returncode,
                                                                   p.stderr))
        elif "Output/Directory" not in p.stderr or outdir not in p.stderr:
            fail("output directory %s: the message does not name it: %s" % (outdir, p.stderr))

    # A folder where a result file goes: refused before the solve, nothing written.
    outdir = os.path.join(work, "folder in the way")
    shutil.rmtree(outdir, ignore_errors=True)
    os.makedirs(os.path.join(outdir, "solution_0001.vtu"))
    p = run(exe, prm, outdir)
    if p.returncode != 1 or "solution_0001.vtu" not in p.stderr:
        fail("a folder named solution_0001.vtu: exit %d, expected 1 naming it (%s)"
             % (p.returncode, p.stderr))
    left = [n for n in looks_like_results(outdir) if n != "solution_0001.vtu"]
    if left:
        fail("a folder named solution_0001.vtu: files that look like a result: %s" % left)
    return 0


def locked(exe, prm_dir, work):
    outdir = os.path.join(work, "locked")
    shutil.rmtree(outdir, ignore_errors=True)
    os.makedirs(outdir)
    prm = os.path.join(prm_dir, "brick_contact.prm")
    lock = os.path.join(outdir, "feticontact.lock")

    # A lock held by another process (this test, posing as process 4242).
    with open(lock, "w") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        held.write("4242 otherhost\n")
        held.flush()
        p = run(exe, prm, outdir)
        if p.returncode != 1 or "in use by another run" not in p.stderr or "4242" not in p.stderr:
            fail("a run into a locked folder: exit %d, stderr %r" % (p.returncode, p.stderr))
        if sorted(os.listdir(outdir)) != ["feticontact.lock"]:
            fail("a refused run changed the locked folder: %s" % os.listdir(outdir))
        with open(lock) as f:
            if f.read() != "4242 otherhost\n":
                fail("a refused run changed the lock file of the run that holds it")
        p = subprocess.run([exe, "--validate", "--set", "Output/Directory=" + outdir, prm],
                           capture_output=True, text=True, env=ENV)
        if p.returncode != 0:
            fail("--validate of a scene whose folder is locked: exit %d" % p.returncode)

    # The lock file left by a process that ended without removing it.
    p = run(exe, prm, outdir)
    if p.returncode != 0 or "took over the lock file" not in p.stderr:
        fail("a run over a stale lock: exit %d, stderr %r" % (p.returncode, p.stderr))
    if os.path.exists(lock):
        fail("the lock file remains after the run")
    check_complete(outdir, "run over a stale lock")

    # Two runs at once: the second starts while the first solves.
    first = command(exe, prm, outdir, ["Body 1/Mesh/Subdivisions=48, 16, 16"])
    print("$", " ".join(first), "(then a second run into the same folder)", flush=True)
    proc = subprocess.Popen(first, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=ENV,
                            text=True)
    log = os.path.join(outdir, "log.txt")
    os.remove(log)  # the earlier run's
    deadline = time.time() + 120
    while time.time() < deadline and proc.poll() is None:
        if os.path.exists(log) and "FETI:" in open(log, errors="replace").read():
            break
        time.sleep(0.05)
    if proc.poll() is not None:
        fail("the first run ended (exit %d) before the second started" % proc.returncode)
        return 0
    with open(lock) as f:
        if f.read().split()[0] != str(proc.pid):
            fail("the lock file does not name the running process %d" % proc.pid)
    p = run(exe, prm, outdir)
    if p.returncode != 1 or str(proc.pid) not in p.stderr:
        fail("the second run: exit %d, stderr %r" % (p.returncode, p.stderr))
    _, stderr = proc.communicate(timeout=600)
    if proc.returncode != 0:
        fail("the first run: exit %d: %s" % (proc.returncode, stderr))
    check_complete(outdir, "the first of two runs")
    # The first run's mesh: 49 × 17 × 17 vertices, the face x = xmin clamped.
    with open(os.path.join(outdir, "summary.json")) as f:
        if json.load(f).get("n_primal", 0) != 3 * (49 - 1) * 17 * 17:
            fail("summary.json is not the first run's")
    with open(os.path.join(outdir, "parameters.prm")) as f:
        if "48, 16, 16" not in f.read():
            fail("parameters.prm is not the first run's")
    if os.path.exists(lock):
        fail("the lock file remains after the first run")
    return 0


def main():
    exe, prm_dir, work, check = sys.argv[1:5]
    np = int(sys.argv[sys.argv.index("--np") + 1]) if "--np" in sys.argv else 1
    os.makedirs(work, exist_ok=True)
    if check == "full-device":
        status = full_device(exe, prm_dir, work, np)
    elif check == "clean":
        status = clean(exe, prm_dir, work, "--fclib" in sys.argv)
    elif check == "killed":
        status = killed(exe, prm_dir, work)
    elif check == "locked":
        status = locked(exe, prm_dir, work)
    elif check == "unwritable":
        status = unwritable(exe, prm_dir, work)
    else:
        sys.exit("unknown check " + check)
    if failures:
        sys.exit("%d check(s) failed" % len(failures))
    sys.exit(status)


if __name__ == "__main__":
    main()
