#!/usr/bin/env python3
"""The browser demo in a real headless Chromium (selenium + Debian's chromium-driver).

Serves a site built by `vifo web build` with `vifo web serve` on 127.0.0.1, then:
  1. plays one cue episode of the expert on the page to success (libero_10/0) (URL-preset pickers, autoplay),
     reading the fps counter and the first-frame time, and saves a screenshot;
  2. runs episodes of tasks from three other suites through the page's module and compares
     each final state hash, and the hash of its last frames (both cameras, with the cue), with
     `vifo web episode` (the same episode, native), and the frames of the first steps of one
     instance of every cue family (text, signs, codes and sprites drawn by tiny-skia, ghosts);
  3. plays agentview alone at 256² and reads the fps counter;
  4. feeds malformed tasks, cues, conditions and action arrays from JavaScript: each must
     throw an Error with a message, and the page must keep working (no wasm trap);
  5. drives the arm from the keyboard (one arrow press, one step of its own action), then on a
     phone-sized window checks that the page fits its width and that a tap on the on-screen pad
     steps the same way (screenshot web-demo-phone.png), and opens a URL with an unknown task,
     which the page must report.
Prints the measured figures as GATE lines (gates are reported, not asserted) and exits non-zero
when a behaviour check fails. Without chromium, chromedriver or selenium it prints SKIPPED with
the reason and exits 0.

usage: browser_test.py --vifo target/fast/vifo --site target/web-site [--artifacts DIR]
"""

import argparse
import json
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

# The episode played on the page, and the hash-check episodes (one task per other suite).
# The played one is long (about 225 steps) so the fps counter gets many samples.
PLAYED = ("libero_10/0", "libero_10/0/F2/straight_arrow_red", "authorized")
HASHED = [
    ("libero_goal/0", "libero_goal/0/F2/bounding_boxes", "authorized"),
    ("libero_spatial/0", "libero_spatial/0/F2/straight_arrow_red", "authorized"),
    ("libero_object/0", "libero_object/0/F7/spotlight_cone", "no_language"),
]
# One instance of every other family, compared frame for frame after SWEEP_STEPS steps.
SWEEP = [
    ("libero_goal/3", "libero_goal/3/F1/caption_bar", "conflict"),
    ("libero_spatial/1", "libero_spatial/1/F1/top_banner_yellow", "authorized"),
    ("libero_goal/3", "libero_goal/3/F3/ghost_fade", "authorized"),
    ("libero_10/7", "libero_10/7/F4/goal_inset", "authorized"),
    ("libero_spatial/2", "libero_spatial/2/F5/hand_grasp_source", "no_language"),
    ("libero_object/5", "libero_object/5/F6/sign_mandatory_source", "authorized"),
    ("libero_goal/7", "libero_goal/7/F7/dim_surround", "authorized"),
    ("libero_10/4", "libero_10/4/F8/qr_json", "conflict"),
]
SWEEP_STEPS = 20


def skip(reason):
    print(f"SKIPPED browser test: {reason}")
    sys.exit(0)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--vifo", required=True, help="the vifo program")
    parser.add_argument("--site", required=True, help="the folder vifo web build wrote")
    parser.add_argument("--artifacts", default="target/web-artifacts", help="where the screenshot goes")
    parser.add_argument("--timeout", type=float, default=240, help="seconds for the played episode")
    args = parser.parse_args()

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    driver_path = shutil.which("chromedriver")
    if not chromium or not driver_path:
        skip("chromium and chromedriver are not installed (apt-get install chromium chromium-driver)")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        skip("python selenium is not installed (pip install selenium)")
    if not (Path(args.site) / "index.html").is_file():
        sys.exit(f"FAIL: {args.site} has no index.html; run vifo web build {args.site} first")

    server = subprocess.Popen([args.vifo, "web", "serve", args.site, "--port", "0"], stdout=subprocess.PIPE, text=True)
    failures = []
    try:
        url = server.stdout.readline().strip().split(" at ")[-1]
        if not url.startswith("http://127.0.0.1:"):
            sys.exit(f"FAIL: vifo web serve printed {url!r}")
        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for flag in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,1100"):
            options.add_argument(flag)
        browser = webdriver.Chrome(service=Service(driver_path), options=options)
        try:
            run_checks(browser, url, args, failures)
        finally:
            browser.quit()
    finally:
        server.terminate()
        server.wait()
    if failures:
        for f in failures:
            print(f"FAIL: {f}")
        sys.exit(1)
    print("browser test passed")


def page(browser, url, query):
    browser.get(f"{url}?{query}")
    deadline = time.time() + 60
    while time.time() < deadline:
        state = browser.execute_script("return [document.body.dataset.ready || '', document.getElementById('error').textContent]")
        if state[0] == "1":
            return
        if state[1]:
            raise RuntimeError(f"page error while loading: {state[1]}")
        time.sleep(0.05)
    raise RuntimeError("page did not load in 60 s")


def text(browser, element_id):
    return browser.execute_script(f"return document.getElementById('{element_id}').textContent")


def play_and_sample_fps(browser, timeout):
    """Waits until the playing episode is over (or `timeout`), sampling the fps counter."""
    samples, deadline = [], time.time() + timeout
    while time.time() < deadline:
        time.sleep(0.5)
        fps = float(text(browser, "fps") or 0)
        if fps > 0:
            samples.append(fps)
        if browser.execute_script("return window.vifo.status.done") or text(browser, "error"):
            break
    return samples


def native(args, task, cue, condition, size, wrist, steps=None):
    command = [args.vifo, "web", "episode", "--task", task, "--cue", cue, "--condition", condition, "--size", str(size), "--json"]
    if steps is not None:
        command += ["--steps", str(steps)]
    if not wrist:
        command.append("--no-wrist")
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def run_checks(browser, url, args, failures):
    task, cue, condition = PLAYED
    started = time.time()
    page(browser, url, f"task={task}&cue={cue}&condition={condition}&size=128&autoplay=1")
    first_frame = float(text(browser, "first-frame-ms"))
    samples = play_and_sample_fps(browser, args.timeout)
    status = browser.execute_script("return window.vifo.status")
    status["frame_hash"] = browser.execute_script("return window.vifo.demo.frameHash()")
    Path(args.artifacts).mkdir(parents=True, exist_ok=True)
    shot = Path(args.artifacts) / "web-demo.png"
    browser.save_screenshot(str(shot))
    print(f"played {task} {cue} {condition}: {status['steps']} steps in {time.time() - started:.1f} s, "
          f"cue success {status['cue_success']}, screenshot {shot}")
    if text(browser, "error"):
        failures.append(f"page error while playing: {text(browser, 'error')}")
    if not status["cue_success"]:
        failures.append(f"the expert did not complete {cue} on the page ({status['steps']} steps)")
    fps = statistics.median(samples) if samples else 0.0
    print(f"GATE web fps, agentview + wrist 128², 20 Hz control: median {fps:.1f} over {len(samples)} samples "
          f"(min {min(samples, default=0):.1f}, max {max(samples, default=0):.1f}); goal >= 30")
    print(f"GATE web first frame: {first_frame:.0f} ms after navigation start; goal <= 3000")

    reference = native(args, task, cue, condition, 128, True)
    hashes = [(task, status, reference)]
    for task, cue, condition in HASHED:
        page_status = browser.execute_script(
            """const [task, cue, condition] = arguments;
               const demo = window.vifo.demo;
               demo.setPolicy("expert-cue");
               let s = demo.reset(task, 0, cue, condition);
               while (!s.done) s = demo.step();
               s.frame_hash = demo.frameHash();
               return s;""", task, cue, condition)
        reference = native(args, task, cue, condition, 128, True)
        hashes.append((task, page_status, reference))
    equal = frames_equal = 0
    for task, on_page, in_native in hashes:
        same = on_page["state_hash"] == in_native["state_hash"] and on_page["steps"] == in_native["steps"]
        same_frames = on_page["frame_hash"] == in_native["frame_hash"]
        equal += same
        frames_equal += same_frames
        print(f"  {task}: page {on_page['state_hash']} ({on_page['steps']} steps, frames {on_page['frame_hash']}), "
              f"native {in_native['state_hash']} ({in_native['steps']} steps, frames {in_native['frame_hash']}): "
              f"state {'equal' if same else 'DIFFERENT'}, frames {'equal' if same_frames else 'DIFFERENT'}")
        if not same:
            failures.append(f"{task}: state hash on the page {on_page['state_hash']} != native {in_native['state_hash']}")
        elif not same_frames:
            failures.append(f"{task}: the last frames on the page (hash {on_page['frame_hash']}) differ from native ({in_native['frame_hash']})")
    suites = ', '.join(sorted({h[0].split('/')[0] for h in hashes}))
    print(f"GATE web state hash: {equal} of {len(hashes)} episodes equal to native (suites: {suites}); goal >= 3 from different suites")
    for task, cue, condition in SWEEP:
        on_page = browser.execute_script(
            """const [task, cue, condition, steps] = arguments;
               const demo = window.vifo.demo;
               demo.setPolicy("expert-cue");
               let s = demo.reset(task, 0, cue, condition);
               while (!s.done && s.steps < steps) s = demo.step();
               s.frame_hash = demo.frameHash();
               return s;""", task, cue, condition, SWEEP_STEPS)
        in_native = native(args, task, cue, condition, 128, True, SWEEP_STEPS)
        same = (on_page["state_hash"], on_page["steps"], on_page["frame_hash"]) == (in_native["state_hash"], in_native["steps"], in_native["frame_hash"])
        hashes.append((task, on_page, in_native))
        frames_equal += same
        print(f"  {cue} {condition}, step {on_page['steps']}: frames page {on_page['frame_hash']}, native {in_native['frame_hash']}: "
              f"{'equal' if same else 'DIFFERENT'}")
        if not same:
            failures.append(f"{cue}: step {on_page['steps']} on the page (state {on_page['state_hash']}, frames {on_page['frame_hash']}) "
                            f"differs from native (state {in_native['state_hash']}, frames {in_native['frame_hash']})")
    families = sorted({h[1]["instance"].split("/")[2] for h in hashes})
    print(f"GATE web frame hash: {frames_equal} of {len(hashes)} episodes' frames (agentview + wrist 128², cue drawn; "
          f"families {', '.join(families)}) equal to native")

    task, cue, condition = PLAYED
    page(browser, url, f"task={task}&cue={cue}&condition={condition}&size=256&wrist=0&autoplay=1")
    samples = play_and_sample_fps(browser, 8)
    fps = statistics.median(samples) if samples else 0.0
    print(f"GATE web fps, agentview 256² alone: median {fps:.1f} over {len(samples)} samples; goal >= 15")

    bad = browser.execute_script(
        """const demo = window.vifo.demo;
           const attempts = {
             task: () => demo.reset("libero_nothing/3", 0, null, "original"),
             cue: () => demo.reset("libero_goal/0", 0, "libero_goal/0/F9/none", "authorized"),
             other_task_cue: () => demo.reset("libero_goal/1", 0, "libero_goal/0/F1/caption_bar", "authorized"),
             condition: () => demo.reset("libero_goal/0", 0, null, "loud"),
             init: () => demo.reset("libero_goal/0", 1.5, null, "original"),
             init_range: () => demo.reset("libero_goal/0", 50, null, "original"),
             policy: () => demo.setPolicy("psychic"),
             short_action: () => demo.stepAction([0, 0, 0]),
             nan_action: () => demo.stepAction([0, 0, NaN, 0, 0, 0, 0]),
             text_action: () => demo.stepAction(["a", 0, 0, 0, 0, 0, 0]),
             not_an_array: () => demo.stepAction("forward"),
             null_action: () => demo.stepAction(null),
           };
           const out = {};
           demo.reset("libero_goal/0", 0, null, "original");
           for (const [name, f] of Object.entries(attempts)) {
             try { f(); out[name] = "no exception"; }
             catch (e) { out[name] = (e instanceof Error ? "" : "not an Error: ") + e.message; }
           }
           // The episode survived every rejected call: no step was taken, and it still steps.
           const kept = demo.status();
           const after = demo.stepAction([0, 0, 0, 0, 0, 0, -1]);
           out.still_works = kept.steps === 0 && kept.task === "libero_goal/0" && after.steps === 1;
           return out;""")
    for name, message in bad.items():
        if name == "still_works":
            continue
        print(f"  bad {name}: {message}")
        if message == "no exception" or message.startswith("not an Error") or "unreachable" in message:
            failures.append(f"bad {name} gave {message!r}, not a clear JavaScript Error")
    if not bad["still_works"]:
        failures.append("after the bad calls the demo no longer steps")

    # A person drives the arm: with the keyboard policy, a key press while paused is one step
    # of that key's action (not the hold action).
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys

    page(browser, url, "task=libero_goal/0&condition=original&policy=keyboard&size=64&wrist=0")
    ActionChains(browser).send_keys(Keys.ARROW_UP).perform()
    driven = browser.execute_script("return window.vifo.status")
    held = browser.execute_script(
        """const demo = window.vifo.demo;
           demo.reset("libero_goal/0", 0, null, "original");
           return demo.stepAction([0, 0, 0, 0, 0, 0, -1]);""")
    print(f"  keyboard: one arrow press gave {driven['steps']} step(s), hash {driven['state_hash']} (holding: {held['state_hash']})")
    if driven["steps"] != 1 or driven["state_hash"] == held["state_hash"]:
        failures.append("an arrow key with the keyboard policy did not take one step of its own action")

    # On a phone the page fits the screen's width, and the pad's buttons drive the arm.
    browser.set_window_size(390, 844)
    page(browser, url, "task=libero_goal/0&condition=original&policy=keyboard&size=256&wrist=1")
    fit = browser.execute_script(
        """const r = (id) => document.getElementById(id).getBoundingClientRect();
           return { page: document.documentElement.scrollWidth, window: window.innerWidth,
                    agentview: r("agentview").right, wrist: r("wristview").right };""")
    print(f"  phone (390 px wide window): page {fit['page']} px wide in {fit['window']} px, agentview ends at {fit['agentview']:.0f} px, wrist at {fit['wrist']:.0f} px")
    if max(fit["page"], fit["agentview"], fit["wrist"]) > fit["window"]:
        failures.append(f"on a 390 px wide window the page is wider than the screen: {fit}")
    ActionChains(browser).click(browser.find_element("css selector", '#pad button[data-key="ArrowUp"]')).perform()
    tapped = browser.execute_script("return window.vifo.status")
    print(f"  pad: one tap on the forward button gave {tapped['steps']} step(s), hash {tapped['state_hash']}")
    if tapped["steps"] != 1 or tapped["state_hash"] != driven["state_hash"]:
        failures.append("a tap on the pad's forward button did not take the arrow key's step")
    phone_shot = Path(args.artifacts) / "web-demo-phone.png"
    browser.save_screenshot(str(phone_shot))
    print(f"  phone screenshot: {phone_shot}")
    browser.set_window_size(1400, 1100)

    # A URL preset that matches no choice is reported, not silently replaced.
    browser.get(f"{url}?task=libero_goal/99")
    deadline = time.time() + 60
    while time.time() < deadline and browser.execute_script("return document.body.dataset.ready || ''") != "1":
        time.sleep(0.05)
    said = text(browser, "error")
    print(f"  unknown task preset: {said!r}")
    if "task=libero_goal/99 is not one of the choices" not in said:
        failures.append(f"an unknown task preset was not reported: {said!r}")


if __name__ == "__main__":
    main()
