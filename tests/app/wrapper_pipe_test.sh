#!/bin/sh
# tests/app/wrapper_pipe_test.sh SOURCE_DIR LADARVR_BINARY: a reader that closes the pipe
# early (`./ladarvr view --help | head -2`) ends the writer, and nobody reports a death:
#  1. the binary: with SIGPIPE's default it ends at its first write and prints nothing;
#     with SIGPIPE ignored (as some callers leave it) it exits 0 and prints nothing;
#  2. the ./ladarvr wrapper: the command's SIGPIPE death keeps its status (141) and gets
#     no "stopped by signal" line, while a SIGTERM still gets its one line.
# The pipe's reader is closed before the command starts, so every write finds it gone:
# no race with a reader that might read everything first. Inside the Debian 13 root
# (ctest runs there) the wrapper runs natively. Skipped (77) when the binary is not the
# checkout's build/<preset>/app/ladarvr, which is what the wrapper would run.
set -eu
src=$(realpath "$1")
bin=$(realpath "$2")
preset=$(basename "$(dirname "$(dirname "$bin")")")
[ "$bin" = "$src/build/$preset/app/ladarvr" ] || { echo "skip: $bin is not under $src/build/<preset>"; exit 77; }
python3 - "$src/ladarvr" "$bin" "$preset" <<'PY'
import os, signal, subprocess, sys

wrapper, binary, preset = sys.argv[1:]
env = dict(os.environ, LADARVR_PRESET=preset)


def to_closed_pipe(cmd, ignore_sigpipe=False):
    """Runs cmd with stdout a pipe whose reader is already closed: (status, stderr)."""
    r, w = os.pipe()
    os.close(r)
    ignore = (lambda: signal.signal(signal.SIGPIPE, signal.SIG_IGN)) if ignore_sigpipe else None
    try:
        p = subprocess.run(cmd, stdout=w, stderr=subprocess.PIPE, env=env, preexec_fn=ignore, timeout=120)
    finally:
        os.close(w)
    return p.returncode, p.stderr.decode(errors="replace")


def check(ok, what):
    if not ok:
        print("FAIL: " + what, file=sys.stderr)
        sys.exit(1)


# 1. The binary itself.
for args in (["view", "--help"], ["--version"], ["scene", "info"]):
    status, err = to_closed_pipe([binary] + args)
    check(status == -signal.SIGPIPE and err == "", "%s: status %s, stderr %r" % (args, status, err))
    status, err = to_closed_pipe([binary] + args, ignore_sigpipe=True)
    check(status == 0 and err == "", "%s with SIGPIPE ignored: status %s, stderr %r" % (args, status, err))

# 2. Through the wrapper (shell: no build step; the command is the binary, exec'd).
status, err = to_closed_pipe([wrapper, "shell", "-c", 'exec "$0" view --help', binary])
check(status == 141, "wrapper: status %s, expected 141; stderr %r" % (status, err))
check("stopped by signal" not in err and err == "", "wrapper reported the closed pipe: %r" % err)
p = subprocess.run([wrapper, "shell", "-c", "kill -TERM $$"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                   env=env, timeout=120)
err = p.stderr.decode(errors="replace")
check(p.returncode == 143 and err == "ladarvr: stopped by signal SIGTERM (exit 143)\n",
      "wrapper and SIGTERM: status %s, stderr %r" % (p.returncode, err))
PY
echo "wrapper_pipe: ok"
