"""A real single-node Slurm cluster in a temporary folder, for tests: munged,
slurmctld and slurmd (Debian's munge and slurm-wlm) on localhost, with a
configuration, key, sockets, spool and state of their own, on free ports, so
that it neither needs nor disturbs a cluster configured on the machine.

    with LocalSlurm(folder) as slurm:   # sets SLURM_CONF for the commands run inside
        subprocess.run(["sbatch", ...])

The daemons run in the foreground as children of this process and get
SIGTERM if it dies (prctl PR_SET_PDEATHSIG), so none outlives the test; on
leaving the block, the jobs are cancelled and the daemons stopped.

Choices for a container without systemd or cgroups: proctrack/linuxproc and
task/none (no cgroup plugin), SlurmUser=root. Debian 12's Slurm 22.05 has no
accounting storage without slurmdbd (accounting_storage/filetxt was removed
in Slurm 20.11), so accounting is off: sacct answers "accounting storage is
disabled", and the job states come from scontrol (completed jobs are kept for
MinJobAge, here an hour) and the job completion log (jobcomp/filetxt).
"""
import ctypes
import os
import re
import secrets
import shutil
import signal
import socket
import subprocess
import tempfile
import time

PR_SET_PDEATHSIG = 1
DAEMONS = ("munged", "slurmctld", "slurmd")


class SlurmUnavailable(Exception):
    """The daemons cannot run here (the reason is the message)."""


def _die_with_parent():
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM)


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def find_daemon(name):
    return shutil.which(name) or next((p for p in (f"/usr/sbin/{name}", f"/sbin/{name}") if os.path.exists(p)), None)


def check_can_run():
    """Raises SlurmUnavailable when this machine cannot run the daemons."""
    if os.geteuid() != 0:
        raise SlurmUnavailable("slurmd and slurmctld need root (SlurmUser=root; slurmd starts jobs as their "
                               "user) and this test runs as uid %d" % os.geteuid())


class LocalSlurm:
    def __init__(self, folder):
        self.dir = os.path.abspath(folder)
        self.procs = {}
        self.stopped = {}
        self.socket_dir = None
        self.env_before = None

    # --- configuration ---------------------------------------------------------
    def node_line(self):
        """This machine's CPUs, sockets, cores and memory as slurmd sees them
        (`slurmd -C`), for a node named localhost."""
        r = subprocess.run([find_daemon("slurmd"), "-C"], capture_output=True, text=True, check=True)
        line = r.stdout.splitlines()[0]
        fields = [f for f in line.split() if not f.startswith("NodeName=")]
        return "NodeName=localhost NodeAddr=127.0.0.1 " + " ".join(fields)

    def write_config(self):
        d = self.dir
        for sub in ("state", "spool", "log"):
            os.makedirs(os.path.join(d, sub), exist_ok=True)
        # munged refuses a socket in a folder that others cannot traverse (the
        # test's own folder is private), and a key that others can read.
        self.socket_dir = tempfile.mkdtemp(prefix="gp_munge_")
        os.chmod(self.socket_dir, 0o755)
        key = os.path.join(d, "munge.key")
        with open(os.open(key, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), "wb") as f:
            f.write(secrets.token_bytes(1024))
        os.chmod(key, 0o600)
        self.munge_socket = os.path.join(self.socket_dir, "munge.socket")
        self.conf = os.path.join(d, "slurm.conf")
        lines = [
            "ClusterName=gptest",
            "SlurmctldHost=localhost(127.0.0.1)",
            f"SlurmctldPort={_free_port()}",
            f"SlurmdPort={_free_port()}",
            "AuthType=auth/munge",
            "CredType=cred/munge",
            f"AuthInfo=socket={self.munge_socket}",
            "SlurmUser=root",
            "SlurmdUser=root",
            f"StateSaveLocation={d}/state",
            f"SlurmdSpoolDir={d}/spool",
            f"SlurmctldPidFile={d}/slurmctld.pid",
            f"SlurmdPidFile={d}/slurmd.pid",
            f"SlurmctldLogFile={d}/log/slurmctld.log",
            f"SlurmdLogFile={d}/log/slurmd.log",
            "MailProg=/bin/true",
            # No cgroups in a container: processes tracked by their parent
            # ids, no task binding.
            "ProctrackType=proctrack/linuxproc",
            "TaskPlugin=task/none",
            "JobAcctGatherType=jobacct_gather/none",
            "AccountingStorageType=accounting_storage/none",
            "JobCompType=jobcomp/filetxt",
            f"JobCompLoc={d}/log/jobcomp.txt",
            "SelectType=select/cons_tres",
            "SelectTypeParameters=CR_Core_Memory",
            "MpiDefault=none",
            "ReturnToService=2",
            "MinJobAge=3600",
            self.node_line() + " State=UNKNOWN",
            "PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP",
        ]
        with open(self.conf, "w") as f:
            f.write("\n".join(lines) + "\n")

    # --- daemons ---------------------------------------------------------------
    def start_daemon(self, name, args):
        exe = find_daemon(name)
        if exe is None:
            raise RuntimeError(f"{name} is not installed (scripts/install-deps.sh installs munge and slurm-wlm)")
        log = open(os.path.join(self.dir, "log", f"{name}.out"), "w")
        self.procs[name] = subprocess.Popen([exe, *args], stdout=log, stderr=subprocess.STDOUT,
                                            stdin=subprocess.DEVNULL, preexec_fn=_die_with_parent)
        log.close()

    def wait_for(self, what, predicate, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for name, p in self.procs.items():
                if p.poll() is not None:
                    raise RuntimeError(f"{name} exited ({p.returncode}) while waiting for {what}:\n" + self.logs(name))
            if predicate():
                return
            time.sleep(0.3)
        raise RuntimeError(f"timed out after {timeout} s waiting for {what}:\n" + self.logs())

    def logs(self, *names):
        out = []
        for name in names or DAEMONS:
            for path in (os.path.join(self.dir, "log", f"{name}.out"), os.path.join(self.dir, "log", f"{name}.log")):
                if os.path.isfile(path):
                    with open(path, errors="replace") as f:
                        tail = f.read().splitlines()[-15:]
                    out.append(f"--- {path}\n" + "\n".join(tail))
        return "\n".join(out)

    def node_state(self):
        r = subprocess.run(["sinfo", "--noheader", "--format=%t"], capture_output=True, text=True)
        return r.stdout.strip() if r.returncode == 0 else ""

    def start(self):
        check_can_run()
        self.write_config()
        self.env_before = os.environ.get("SLURM_CONF")
        os.environ["SLURM_CONF"] = self.conf
        d = self.dir
        self.start_daemon("munged", ["--foreground", f"--key-file={d}/munge.key", f"--socket={self.munge_socket}",
                                     f"--pid-file={d}/munged.pid", f"--log-file={d}/log/munged.log",
                                     f"--seed-file={d}/munged.seed"])
        self.wait_for("munged's socket", lambda: os.path.exists(self.munge_socket), 20)
        self.start_daemon("slurmctld", ["-D", "-f", self.conf])
        self.start_daemon("slurmd", ["-D", "-N", "localhost", "-f", self.conf])
        self.wait_for("the node to be idle", lambda: self.node_state() == "idle", 60)

    def cancel_jobs(self, timeout=60):
        r = subprocess.run(["squeue", "--noheader", "--format=%i"], capture_output=True, text=True)
        ids = r.stdout.split() if r.returncode == 0 else []
        if ids:
            subprocess.run(["scancel", *ids], capture_output=True)
        end = time.monotonic() + timeout
        while ids and time.monotonic() < end:
            r = subprocess.run(["squeue", "--noheader", "--format=%i"], capture_output=True, text=True)
            if r.returncode != 0 or not r.stdout.strip():
                break
            time.sleep(0.5)

    def stop(self):
        if "slurmctld" in self.procs and self.procs["slurmctld"].poll() is None:
            self.cancel_jobs()
        # The job steps' processes are gone with their jobs; stop the daemons
        # in the reverse order of their start.
        for name in reversed(DAEMONS):
            p = self.procs.get(name)
            if p is None or p.poll() is not None:
                continue
            p.terminate()
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        self.stopped, self.procs = self.procs, {}
        if self.socket_dir:
            shutil.rmtree(self.socket_dir, ignore_errors=True)
        if self.env_before is None:
            os.environ.pop("SLURM_CONF", None)
        else:
            os.environ["SLURM_CONF"] = self.env_before

    def running(self):
        """The daemons this object started that are still running."""
        return [n for n, p in {**self.stopped, **self.procs}.items() if p.poll() is None]

    def __enter__(self):
        try:
            self.start()
        except BaseException:
            self.stop()
            raise
        return self

    def __exit__(self, *exc):
        self.stop()
        return False


def version():
    r = subprocess.run(["sinfo", "--version"], capture_output=True, text=True)
    m = re.search(r"(\d+\.\d+\.\d+)", r.stdout)
    return m.group(1) if m else None
