"""The data path under load: generated ROS 1 writers into one generated service, and the
delay its readers add.

    .venv/bin/python bench/data_path.py [--writers 10] [--rate 100] [--seconds 60]

A product line written here has one store (positions in arc-seconds refined to degrees,
``lat / 3600`` every ``--period`` seconds, SQLite) and, in one robot container, a writer and two
readers of the refined records: one polling every second, one subscribed over the
store's WebSocket. The bench resolves it with spl, starts one roscore, the generated
service (uvicorn, its own process) and ``--writers`` copies of the generated ROS 1
writer node (``clients/ros1/<writer>``, each its own robot id), each fed at ``--rate``
Hz by a rospy publisher for ``--seconds``, and both generated readers, each watched by
a rospy subscriber that stamps every message it receives.

Printed: records published, stored (and lost or duplicated: must be 0), refined; then
for each reader the delay it adds, from the commit of a refined row (an SQLite trigger
stamps the insert, inside the transformer's transaction) to the reader's subscriber
receiving it, p50 and p99 over every record. Goals: polling at most the poll period
plus 50 ms; subscribed at most 50 ms at p99. Each commit refines what arrived in one
period (``--writers * --rate * --period`` rows), and a subscriber gets them one after
the other: the last row of a commit waits for the others.
"""

from __future__ import annotations

import argparse
import json
import sqlite3
import statistics
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from spl.generators.bundle.writer import bundle_files, write_bundle  # noqa: E402
from spl.resolver.resolution.engine import resolve  # noqa: E402
from spl.resolver.resolution.product_line import load_product_line  # noqa: E402
from spl.resolver.resolution.product_selection import selection_from_list  # noqa: E402
from spl.smoke.planning import data_fields  # noqa: E402
from spl.smoke.processes import Processes, find_ros, free_port, write_messages  # noqa: E402

TSM = """system Bench
data Seconds {
    lat : double
    lon : double
}
data Degrees {
    lat : double
    lon : double
}
transform ToDegrees : Seconds -> Degrees {
    lat = lat / 3600.0
    lon = lon / 3600.0
}
cloud container Cloud {
    store Positions {
        raw Seconds
        refined Degrees by ToDegrees every PERIOD s
    }
}
robot container Robot {
    endpoint robot_id "robot_0" url "wss://cloud.example.org:9000/" user "u" password env "P"
    topic In : bench_msgs/Seconds name "/in"
    topic Polled : bench_msgs/Degrees name "/polled"
    topic Pushed : bench_msgs/Degrees name "/pushed"
    writer Writer : Seconds to Cloud.Positions <- In
    reader Poller : Degrees from Cloud.Positions -> Polled every 1 s
    reader Pusher : Degrees from Cloud.Positions -> Pushed subscribe every 1 s
}
"""

PUBLISHER = """
import sys, time, rospy
from bench_msgs.msg import Seconds
robot, rate, seconds = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
rospy.init_node(f"feed_{robot}")
pub = rospy.Publisher("out", Seconds, queue_size=1000)
deadline = time.monotonic() + 20
while pub.get_num_connections() < 1 and time.monotonic() < deadline:
    time.sleep(0.05)
time.sleep(0.3)
period, count = 1.0 / rate, int(rate * seconds)
start = time.monotonic()
for seq in range(count):
    pub.publish(Seconds(lat=robot * 1e7 + seq, lon=float(seq)))
    pause = start + (seq + 1) * period - time.monotonic()
    if pause > 0:
        time.sleep(pause)
print(count, flush=True)
rospy.sleep(1.0)
"""

WATCHER = """
import json, sys, time, rospy
from bench_msgs.msg import Degrees
topic, seconds, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
rospy.init_node("watch_" + topic.strip("/"))
got = []
rospy.Subscriber(topic, Degrees, lambda m: got.append((m.lat, time.time())), queue_size=100000)
end = time.monotonic() + seconds
while time.monotonic() < end and not rospy.is_shutdown():
    time.sleep(0.2)
with open(out, "w") as f:
    json.dump(got, f)
"""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--writers", type=int, default=10)
    parser.add_argument("--rate", type=float, default=100.0)
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument(
        "--period", type=float, default=1.0,
        help="the transformer's period in the model (s): each commit refines what came since",
    )  # fmt: skip
    args = parser.parse_args()
    ros = find_ros()
    with tempfile.TemporaryDirectory(prefix="spl-bench-data-") as scratch:
        run(Path(scratch), ros, args)


def run(scratch: Path, ros, args) -> None:  # type: ignore[no-untyped-def]
    line = scratch / "line"
    line.mkdir()
    (line / "b.tsm").write_text(TSM.replace("PERIOD", repr(args.period)))
    (line / "b.fm").write_text("feature model Bench\nroot Bench\n")
    (line / "b.rm").write_text('resolution model Bench\ntsm "b.tsm"\nfm "b.fm"\n')
    product = resolve(load_product_line(line), selection_from_list("Bench")).product
    bundle = scratch / "bundle"
    write_bundle(bundle_files(product), bundle)
    messages = scratch / "messages"
    fields = data_fields(product.system)
    write_messages(messages, {
        kind: f"string TYPE={kind}\n" + "".join(
            f"{'float64' if t == 'double' else t} {n}\n" for n, t in names)
        for kind, names in fields.items()
    })  # fmt: skip
    database = scratch / "positions.db"
    port, master = free_port(), free_port()
    token = "bench-token"
    with Processes(scratch) as processes:
        env = processes.environment(
            ROS_MASTER_URI=f"http://127.0.0.1:{master}/", ROS_IP="127.0.0.1",
            ROS_HOME=str(scratch / "ros"), PYTHONPATH=str(messages),
        )  # fmt: skip
        processes.start("roscore", [ros.roscore, "-p", str(master)], env)
        service = bundle / "services" / "Positions"
        processes.start(
            "service",
            [sys.executable, "-m", "positions_service"],
            processes.environment(
                PYTHONPATH=str(service), DATABASE_URL=f"sqlite:///{database}",
                HOST="127.0.0.1", PORT=str(port), POSITIONS_TOKEN=token,
            ),
        )  # fmt: skip
        url = f"http://127.0.0.1:{port}"
        wait_until(lambda: urllib.request.urlopen(url + "/", timeout=1).status == 200)  # nosec B310
        stamp_commits(database)
        time.sleep(2.0)  # the master
        node_env = {**env, "POSITIONS_TOKEN": token}
        scripts = bundle / "clients" / "ros1"

        def node(package: str, name: str, *extra: str) -> None:
            path = [str(messages), str(scripts / package / "src")]
            processes.start(
                name,
                [ros.python, str(scripts / package / "scripts" / package), f"__name:={name}",
                 f"_store_url:={url}", *extra],
                {**node_env, "PYTHONPATH": ":".join(path)},
            )  # fmt: skip

        watch = args.seconds + 25.0
        results = {}
        for reader, topic in (("poller", "/polled"), ("pusher", "/pushed")):
            node(reader, reader, f"records:={topic}")
            results[reader] = scratch / f"{reader}.json"
            processes.start("watch-" + reader,
                            [ros.python, "-c", WATCHER, topic, str(watch), str(results[reader])],
                            node_env)  # fmt: skip
        for robot in range(args.writers):
            node("writer", f"writer_{robot}", f"_robot_id:=robot_{robot}",
                 f"records:=/in_{robot}")  # fmt: skip
            processes.start(
                f"feed-{robot}",
                [ros.python, "-c", PUBLISHER, str(robot), str(args.rate), str(args.seconds),
                 f"out:=/in_{robot}"],
                node_env,
            )  # fmt: skip
        print(f"{args.writers} writers at {args.rate:g} Hz for {args.seconds:g} s ...", flush=True)
        wait_until(lambda: all(p.is_file() for p in results.values()), timeout=watch + 30)
        report(database, results, args)


def wait_until(condition, timeout: float = 60.0) -> None:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            if condition():
                return
        except OSError:
            pass
        time.sleep(0.2)
    raise SystemExit("timed out")


def stamp_commits(database: Path) -> None:
    """A trigger stamping each refined row's insert (inside the transformer's transaction,
    which commits right after it) with the wall clock, to the millisecond."""
    db = sqlite3.connect(database)
    table = next(
        name for (name,) in db.execute("select name from sqlite_master where type='table'")
        if name.endswith("degrees")
    )  # fmt: skip
    db.executescript(f"""
        create table bench_commits (id integer primary key, at real);
        create trigger bench_stamp after insert on "{table}" begin
            insert into bench_commits values (new.id, (julianday('now') - 2440587.5) * 86400.0);
        end;
    """)
    db.close()


def report(database: Path, results: dict[str, Path], args) -> None:  # type: ignore[no-untyped-def]
    db = sqlite3.connect(database)
    tables = {name for (name,) in db.execute("select name from sqlite_master where type='table'")}
    raw = next(t for t in tables if t.endswith("raw") or t.endswith("records"))
    refined = next(t for t in tables if t.endswith("degrees"))
    published = int(args.writers * args.rate * args.seconds)
    stored = db.execute(f'select count(*) from "{raw}"').fetchone()[0]  # nosec B608
    distinct = db.execute(
        f"""select count(*) from (select distinct robot, json_extract(document, '$.lat')
            from "{raw}")"""  # nosec B608
    ).fetchone()[0]
    commits = dict(db.execute(
        f'select r.lat, c.at from "{refined}" r join bench_commits c on c.id = r.id'  # nosec B608
    ).fetchall())  # fmt: skip
    print(f"published {published}, stored {stored} ({published - distinct} lost, "
          f"{stored - distinct} duplicated), refined {len(commits)}")  # fmt: skip
    for reader, path in results.items():
        got = json.loads(path.read_text())
        delays = sorted(
            (at - commits[lat]) * 1000 for lat, at in got if lat in commits
        )  # fmt: skip
        if not delays:
            print(f"{reader}: nothing received")
            continue
        p50 = statistics.median(delays)
        p99 = delays[min(len(delays) - 1, int(len(delays) * 0.99))]
        print(f"{reader}: {len(got)} received, delay commit -> subscriber: p50 {p50:.1f} ms, "
              f"p99 {p99:.1f} ms")  # fmt: skip


if __name__ == "__main__":
    main()
