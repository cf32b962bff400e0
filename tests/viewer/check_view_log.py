#!/usr/bin/env python3
"""tests/viewer/check_view_log.py SCENARIO LOG.json SHOT.png STDERR: the assertions of
view_headless_test.sh on the viewer's run log (--log-json) and mirror screenshot."""
import json
import math
import struct
import sys
import zlib

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
    return condition


def read_png(path):
    """Decodes 8-bit RGB PNGs (any of the five row filters) into (w, h, bytes)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG signature"
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        (crc,) = struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])
        assert zlib.crc32(kind + body) == crc, f"bad CRC in chunk {kind!r}"
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert (depth, colour) == (8, 2), "expected 8-bit RGB"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    row = width * 3
    assert len(raw) == (row + 1) * height, "wrong image data size"
    pixels, prior = bytearray(), bytearray(row)
    for y in range(height):
        kind, line = raw[y * (row + 1)], bytearray(raw[y * (row + 1) + 1:(y + 1) * (row + 1)])
        assert kind <= 4, f"unknown PNG filter {kind}"
        for i in range(row):  # PNG specification, section 9: a = left, b = up, c = up-left
            a = line[i - 3] if i >= 3 else 0
            b = prior[i]
            c = prior[i - 3] if i >= 3 else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        pixels += line
        prior = line
    return width, height, pixels


def count(pixels, predicate):
    return sum(1 for i in range(0, len(pixels), 3) if predicate(pixels[i], pixels[i + 1], pixels[i + 2]))


def quat_angle_deg(a, b):
    dot = abs(sum(x * y for x, y in zip(a, b)))
    return math.degrees(2.0 * math.acos(min(1.0, dot)))


def rotate(q, v):
    """Rotates v by the unit quaternion q = [w, x, y, z]."""
    w, x, y, z = q
    # v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    c = (y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0])
    cc = (y * c[2] - z * c[1], z * c[0] - x * c[2], x * c[1] - y * c[0])
    return tuple(v[i] + 2.0 * w * c[i] + 2.0 * cc[i] for i in range(3))


# The simulated HMD's per-eye field of view (Monado's simulated device, both eyes):
# 42.5 deg either side, 44.62 deg up and down.
MONADO_SIMULATED_FOV_RAD = (-0.7417649030685425, 0.7417649030685425, 0.7787635922431946, -0.7787635922431946)


def dist(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def check_screenshot(shot, want_label_red):
    w, h, px = read_png(shot)
    check((w, h) == (960, 540), f"screenshot is {w}x{h}, expected the 960x540 window")
    background = (15, 18, 23)  # the clear colour 0.06, 0.07, 0.09
    lit = count(px, lambda r, g, b: abs(r - background[0]) + abs(g - background[1]) + abs(b - background[2]) > 30
                and (r, g, b) != (0, 0, 0))
    check(lit > 0.15 * w * h, f"screenshot nearly empty: {lit} of {w * h} pixels show something")
    if want_label_red:   # --colour label: pure red is the target's ground-truth colour
        red = count(px, lambda r, g, b: r > 150 and g < 40 and b < 40)
    else:                # file colours: the jet map is red at the lowest heights (the target)
        red = count(px, lambda r, g, b: r > 180 and g < 90 and b < 90)
    check(red >= 20, f"only {red} red target pixels in the screenshot (want >= 20)")
    plate = count(px, lambda r, g, b: abs(r - 0) < 12 and abs(g - 158) < 12 and abs(b - 230) < 12)
    check(plate > 100, f"the AUTOMATIC mode plate is not in the screenshot ({plate} pixels)")
    print(f"screenshot {w}x{h}: {lit} lit, {red} red, {plate} mode-plate pixels")


def check_toggles(log, frames):
    switches = [(s["frame"], s["from"], s["to"]) for s in log["mode_switches"]]
    check(switches == [(10, "automatic", "free"), (25, "free", "automatic")],
          f"mode switches {switches}, expected automatic->free at 10 and back at 25")
    modes = {f["frame"]: f["mode"] for f in frames}
    want = {i: ("free" if 11 <= i <= 25 else "automatic") for i in modes}
    wrong = [i for i in modes if modes[i] != want[i]]
    check(not wrong, f"frames with the wrong mode: {wrong[:10]}")
    check(log["mode_final"] == "automatic", "final mode is not automatic")


def check_orbit(log, frames):
    """Automatic frames ride the orbit: 60 m out and 40 m up from the centre (render defaults);
    free frames stay where the switch left the user (no motion was requested).
    The centre follows the cloud's bounds while it streams in, so each frame is checked
    against the centre it was drawn with."""
    for f in frames:
        c = f["orbit_centre_local"]
        p = f["eyes_local"][0]["position"]
        if f["mode"] == "automatic":
            r = math.hypot(p[0] - c[0], p[1] - c[1])
            if not check(abs(r - 60.0) < 0.6 and abs(p[2] - c[2] - 40.0) < 0.6,
                         f"frame {f['frame']}: automatic eye at radius {r:.2f} m, height {p[2] - c[2]:.2f} m"):
                return
    free = [f for f in frames if f["mode"] == "free"]
    if check(len(free) >= 5, "too few free frames"):
        spread = max(dist(f["eyes_local"][0]["position"], free[0]["eyes_local"][0]["position"]) for f in free)
        check(spread < 0.6, f"free mode moved {spread:.2f} m without any motion input")


def main():
    scenario, log_path, shot, stderr_path = sys.argv[1:5]
    log = json.load(open(log_path))
    stderr = open(stderr_path).read()
    frames = log["frames"]
    print(f"{scenario}: exit={log['exit']} states={log['states']} frames={log['frames_counted']} "
          f"submitted={log['frames_submitted']} fallback={log['fallback']!r}")
    # Escape at frame 5 may come before the generator has finished; every other scenario
    # runs long enough to have the whole cloud on the GPU.
    if scenario != "escape":
        check(log["points_uploaded"] == 163840, f"{log['points_uploaded']} points on the GPU, expected 163840")

    if scenario == "xr":
        states = log["states"]
        order = ["IDLE", "READY", "SYNCHRONIZED", "VISIBLE", "FOCUSED"]
        check(states[:5] == order, f"states {states[:5]}, expected {order}")
        check(states[-3:] == ["STOPPING", "IDLE", "EXITING"], f"clean close: last states {states[-3:]}")
        check(log["xr_active_at_start"] and log["fallback"] == "", "the XR session did not start")
        check(log["xr_system"].startswith("Monado"), f"system {log.get('xr_system')}")
        check(log["xr_swapchain_format"] in log["xr_formats_offered"], "swapchain format not offered")
        check(log["exit"] == "frames", f"exit {log['exit']}")
        check(log["frames_submitted"] == 40 and len(frames) == 40,
              f"{log['frames_submitted']} frames submitted / {len(frames)} logged, expected 40")
        for f in frames:
            check(f["xr"] and len(f["eyes_tracking"]) == 2 and len(f["eyes_local"]) == 2,
                  f"frame {f['frame']}: not both eyes")
            e = f["eyes_tracking"]
            ipd = dist(e[0]["position"], e[1]["position"])
            ipd_local = dist(f["eyes_local"][0]["position"], f["eyes_local"][1]["position"])
            check(0.04 < ipd < 0.09, f"frame {f['frame']}: eye separation {ipd:.4f} m")
            # The rig is rigid: the rendered eyes are the runtime's eyes moved as one.
            check(abs(ipd - ipd_local) < 1e-4, f"frame {f['frame']}: rendered eyes {ipd_local} vs runtime {ipd}")
            # Each eye's field of view is the runtime's: Monado's simulated HMD declares the
            # same symmetric one for both eyes (left, right, up, down, radians).
            for i, x in enumerate(e):
                fov = x.get("fov_rad", [])
                check(len(fov) == 4 and all(abs(a - b) < 1e-6 for a, b in zip(fov, MONADO_SIMULATED_FOV_RAD)),
                      f"frame {f['frame']}: eye {i} fov {fov}, the runtime's is {MONADO_SIMULATED_FOV_RAD}")
            # Eye 0 is the left eye: the right eye lies along the head's +x (the runtime's
            # frame), and along the rendered view's right (gaze x world up) in the scene.
            head_right = rotate(e[0]["orientation"], (1.0, 0.0, 0.0))
            along = sum((b - a) * r for a, b, r in zip(e[0]["position"], e[1]["position"], head_right))
            check(along > 0.04, f"frame {f['frame']}: right eye {along:.4f} m along the head's right, not the left eye's right")
            g = f["eyes_local"][0]["gaze"]
            view_right = (g[1], -g[0], 0.0)
            norm = math.hypot(view_right[0], view_right[1])
            p0, p1 = f["eyes_local"][0]["position"], f["eyes_local"][1]["position"]
            along_local = sum((b - a) * r / norm for a, b, r in zip(p0, p1, view_right)) if norm > 0.1 else 0.0
            check(along_local > 0.03, f"frame {f['frame']}: rendered right eye {along_local:.4f} m to the right of the left")
        q = [f["eyes_tracking"][0]["orientation"] for f in frames]
        p = [f["eyes_tracking"][0]["position"] for f in frames]
        t = [f["display_time_ns"] for f in frames]
        turn = max(quat_angle_deg(q[0], x) for x in q)
        move = max(dist(p[0], x) for x in p)
        print(f"simulated head: turned up to {turn:.2f} deg, moved up to {move * 1000:.1f} mm "
              f"over {(t[-1] - t[0]) * 1e-9:.2f} s of display time in {len(q)} frames")
        # The simulated head moves with the display time the runtime predicts for each frame,
        # however fast frames come: frames for later display times have other poses.
        check(all(b > a for a, b in zip(t, t[1:])), "display times do not increase frame to frame")
        same = [frames[k + 1]["frame"] for k in range(len(q) - 1)
                if quat_angle_deg(q[k], q[k + 1]) == 0.0 and p[k] == p[k + 1]]
        check(not same, f"frames {same[:10]} repeat the previous frame's head pose: the eye poses do not follow the runtime")
        check_toggles(log, frames)
        check_orbit(log, frames)
        check_screenshot(shot, want_label_red=True)
    elif scenario == "desktop":
        lines = [l for l in stderr.splitlines() if "desktop mode" in l]
        check(len(lines) == 1 and "no OpenXR runtime" in lines[0], f"fallback line(s): {lines}")
        check(not log["xr_active_at_start"] and log["frames_submitted"] == 0, "XR should not be active")
        check(log["frames_counted"] == 40 and len(frames) == 40, f"{log['frames_counted']} desktop frames")
        check(log["states"] == [], "session states without a runtime")
        check_toggles(log, frames)
        check_orbit(log, frames)
        auto = [f for f in frames if f["mode"] == "automatic" and f["frame"] <= 10]
        swept = dist(auto[0]["eyes_local"][0]["position"], auto[-1]["eyes_local"][0]["position"])
        check(swept > 0.05, f"the automatic orbit did not move the eye ({swept:.3f} m)")
        check_screenshot(shot, want_label_red=False)
    elif scenario == "budget":
        check(log["point_budget"] == 40000 and log["cull"] and log["lod_cells"] >= 4, "budget / LOD cells not in the log")
        check(log["points_uploaded"] == 163840, f"{log['points_uploaded']} points uploaded")
        full = [f for f in frames if f["points_uploaded"] == 163840]
        # loaded+5 counts from the upload's end, not from the generator's: with 9 frames of
        # uploading, an Escape timed from the generator would leave no full frame.
        check(len(full) >= 4, f"{len(full)} frames with the whole cloud before loaded+5's Escape, expected >= 4")
        check(len(full) >= 3 and all(30000 < f["points_drawn"] <= 40000 for f in full),
              f"points drawn with a 40,000 budget: {[f['points_drawn'] for f in full]}")
        check_screenshot(shot, want_label_red=True)
    elif scenario == "escape":
        check(log["exit"] == "escape", f"exit {log['exit']}")
        check(log["frames_counted"] == 5, f"{log['frames_counted']} frames before Escape, expected 5")
        # The script's cut (frame 2) and colour (frame 3) act before the next frame is drawn,
        # through the tools as V and C do.
        cuts = [f["cut"] for f in frames]
        check(cuts == [False, False, True, True, True], f"cut flags {cuts}")
        colours = [f["colour"] for f in frames]
        check(len(set(colours[:3])) == 1 and len(set(colours[3:])) == 1 and colours[2] != colours[3],
              f"colour modes {colours}: the script's colour did not step the mode after frame 3")
    elif scenario == "lost":
        check("FOCUSED" in log["states"], "never FOCUSED before the runtime went away")
        check(log["frames_submitted"] >= 1, "no XR frame before the runtime went away")
        check("lost" in log["fallback"] or "failed" in log["fallback"] or "ended" in log["fallback"],
              f"fallback reason {log['fallback']!r}")
        check(not log["xr_active_at_end"], "XR still active at the end")
        after = [f for f in frames if not f["xr"]]
        # Escape is scripted 20 frames after the drop to the desktop (desktop+20).
        check(log["exit"] == "escape" and len(after) == 20 and log["frames_counted"] == log["frames_submitted"] + 20,
              f"exit {log['exit']} after {len(after)} desktop frames ({log['frames_counted']} counted, "
              f"{log['frames_submitted']} submitted), expected escape after 20")
        check(log["frames_submitted"] >= 2, f"the runtime went away after {log['frames_submitted']} XR frames, not 2")
        # The cloud is kept (all 163,840 points on the GPU); the desktop orbit view draws
        # most of it (frustum culling skips the cells outside the 16:9 window: ~86 % drawn).
        check(len(after) >= 5 and all(f["points_uploaded"] == 163840 and 0.6 * 163840 <= f["points_drawn"] <= 163840
                                      for f in after[-3:]),
              "desktop frames after the loss do not draw the kept cloud")
    elif scenario == "stream":
        uploaded = [f["points_uploaded"] for f in frames]
        steps = [b - a for a, b in zip([0] + uploaded, uploaded)]
        print(f"uploaded per frame: {steps}")
        check(max(steps) <= 20000, f"a frame uploaded {max(steps)} points, budget 20000")
        # Points are drawn in the frame that first uploads some, however long reading takes.
        first = next((f for f in frames if f["points_uploaded"] > 0), None)
        if check(first is not None, "no frame uploaded points"):
            check(first["points_drawn"] > 0 and log["first_points_frame"] == first["frame"],
                  f"frame {first['frame']} uploaded the first points but they were first drawn at frame "
                  f"{log['first_points_frame']}")
        check(uploaded[-1] == 163840 and uploaded.index(163840) >= 8,
              "the 163,840 points should take at least 9 frames at 20,000 per frame")
        partial = [f for f in frames if 0 < f["points_drawn"] < 163840]
        check(len(partial) >= 5, "no frames drew a partly uploaded cloud")
        check(log["origin"] == [1e6, 2e6, 50.0], f"origin {log['origin']} not the file's")
        check_screenshot(shot, want_label_red=False)
    else:
        check(False, f"unknown scenario {scenario}")

    for f in failures:
        print("FAIL:", f)
    print("PASS" if not failures else f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
