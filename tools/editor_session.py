#!/usr/bin/env python3
"""A long editing session through the editor's HTTP API (what the page sends): N drags of the
given anchors in turn at neighbourhood DELTA, each a mouse-down frame, one move and a release
that commits; prints the wall time of each and the server's part.

    cargo build --release -p host
    python3 tools/editor_session.py RUN.ron ANCHOR[,ANCHOR...] DELTA N
"""
import json, subprocess, sys, time, urllib.request, random
run, anchors, delta, n = sys.argv[1], sys.argv[2].split(","), int(sys.argv[3]), int(sys.argv[4])
port = 38000 + random.randint(0, 999)
p = subprocess.Popen(["/work/main/target/release/ecles", "edit", run, "--no-token", "--no-autosave", "--port", str(port)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
url = f"http://127.0.0.1:{port}"
for _ in range(200):
    try:
        urllib.request.urlopen(url + "/api/state"); break
    except Exception: time.sleep(0.1)
def drag(body):
    req = urllib.request.Request(url + "/api/drag", data=json.dumps(body).encode(), headers={"content-type": "application/json"})
    t = time.time(); a = json.loads(urllib.request.urlopen(req).read()); return a, (time.time() - t) * 1e3
random.seed(1)
src = json.loads(urllib.request.urlopen(url + "/api/state").read())["sources"][0]["name"]
for i in range(n):
    anchor = anchors[i % len(anchors)]
    sel = {"source": src, "anchors": [anchor], "neighborhood": delta}
    dx, dy = random.randint(-16, 16), random.randint(-16, 16)
    a0, t0 = drag({"selection": sel, "motion": {"translate": {"dx": "0", "dy": "0"}}, "commit": False})
    a1, t1 = drag({"selection": sel, "motion": {"translate": {"dx": f"{dx}/4", "dy": f"{dy}/4"}}, "commit": False})
    a2, t2 = drag({"selection": sel, "motion": {"translate": {"dx": f"{dx}/2", "dy": f"{dy}/2"}}, "commit": True})
    st = json.loads(urllib.request.urlopen(url + "/api/state").read())
    longest = max(len(x) for pt in st["points"] for x in pt["exact"])
    print(f"   server: down {a0.get('server_ms',0):.0f} move {a1.get('server_ms',0):.0f} release {a2.get('server_ms',0):.0f}; init {a0.get('initialized')} frames {a1.get('frames')} planned {a1.get('planned')}")
    print(f"edit {i+1:2d} {anchor:>5}: mouse-down {t0:7.1f} ms, first move {t1:7.1f} ms, release {t2:7.1f} ms, ok {a2.get('committed')}, violated {st['violated_rows']}, longest value {longest} chars", flush=True)
p.kill()
