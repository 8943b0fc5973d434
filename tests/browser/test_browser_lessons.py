"""The five lessons end to end in headless Debian Chromium (Playwright, no bundled browser).

One page of the tier's shared app server and Chromium (the server has ``RINGLAB_LESSONS_SCALE=fast``: the
presets' smaller boxes, so the runs get far enough in seconds).  For every step: "Set up this step" applies the preset (the test checks the
tab it shows and the controls), then the answer is read off the page the way a student would (a
readout card, or 0.85 x the linear maximum growth rate for the measured growth), a wrong answer
is rejected and the right one accepted by the app's check.  A run the check needs is paused first,
so the readout read is the state checked.  Screenshots (1280 x 720) of every step go to
``/tmp/shots/lessons/``.

Run alone with ``python -m pytest -p no:playwright tests/browser/test_browser_lessons.py -q``.
"""
from __future__ import annotations

import math
import re
import time
from pathlib import Path

import pytest

from ringlab.lessons import LESSONS
from ringlab.lessons.worksheets import worksheet_path
from browser_support import CHROMIUM, context, sync_playwright

SHOTS = Path("/tmp/shots/lessons")

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(sync_playwright is None, reason="playwright Python package not installed"),
    pytest.mark.skipif(not CHROMIUM.exists(), reason=f"{CHROMIUM} not found"),
]


@pytest.fixture
def lessons_server(shared_app):
    """URL of the shared app server: RINGLAB_LESSONS_SCALE=fast (tests/browser_support.py)."""
    return shared_app.url


def number(text: str) -> float:
    m = re.search(r"[-+]?\d+\.?\d*(e[-+]?\d+)?", text.replace("−", "-"))
    assert m, text
    return float(m.group(0))


class Student:
    def __init__(self, page):
        self.page = page
        self.attempts = 0
        self.last_pause = {}

    def card(self, rid: str) -> str:
        loc = self.page.locator(f"#{rid} .ro-value", has_text=re.compile(r"[\d—∞]"))
        loc.wait_for()  # a tab shown again is re-rendered (dynamic tabs)
        return loc.inner_text().strip()

    def card_note(self, rid: str) -> str:
        loc = self.page.locator(f"#{rid} .ro-note", has_text=re.compile(r"\d"))
        loc.wait_for()
        return loc.inner_text().strip()

    def set_up(self, tab: str):
        p = self.page
        p.locator(".lesson-setup button").click()
        p.locator("#lesson-setup-result.msg-ok").wait_for(timeout=120_000)
        p.locator(".bk-tab.bk-active", has_text=tab).wait_for(timeout=10_000)

    def answer(self, value, choice: bool):
        p = self.page
        if choice:
            p.locator(".lesson-choice label", has_text=value).first.click()
        else:
            box = p.locator(".lesson-answer input")
            box.fill(str(value))
        self.attempts += 1
        if choice:
            p.wait_for_timeout(150)
            p.locator(".lesson-check button").click()
        else:
            box.press("Enter")  # Enter in the answer box checks it, as the button does
        fb = p.locator(f'[data-attempt="{self.attempts}"]')
        fb.wait_for(timeout=120_000)  # a busy server (live N-body box) may take a few seconds
        return fb.get_attribute("id").rsplit("-", 1)[1]

    def expect(self, value, status: str, choice: bool = False):
        got = self.answer(value, choice)
        text = self.page.locator(f'[data-attempt="{self.attempts}"]').inner_text()
        assert got == status, f"answer {value!r}: expected {status}, got {got}: {text}"
        return text

    def wait_orbits(self, rid: str, orbits: float, timeout_s: float = 60.0):
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < timeout_s:
            txt = self.card(rid)
            if txt not in ("", "—") and number(txt) >= orbits:
                return number(txt)
            self.page.wait_for_timeout(250)
        raise AssertionError(f"#{rid} did not reach {orbits} orbits in {timeout_s} s (last {self.card(rid)})")

    def paused_by_lesson(self, kind: str):
        """Wait until the run has done its classroom length and paused itself (the preset's run_for)."""
        t0 = time.perf_counter()
        loc = self.page.locator(f"#{kind}-status")
        while time.perf_counter() - t0 < 150:
            text = loc.inner_text() if loc.count() else ""
            if "Paused by the lesson" in text and text != self.last_pause.get(kind):
                self.last_pause[kind] = text
                self.page.wait_for_timeout(600)  # frames already queued are applied
                return text
            self.page.wait_for_timeout(250)
        raise AssertionError(f"the {kind} run did not pause itself within 150 s: {loc.inner_text()}")

    def shot(self, name: str):
        fb = self.page.locator('[id^="lesson-feedback-"]')
        if fb.count():
            fb.first.scroll_into_view_if_needed()
        self.page.screenshot(path=str(SHOTS / f"{name}.png"))

    def next(self):
        title = self.page.locator("#lesson-step-title").inner_text()
        self.page.locator(".lesson-next button").click()
        t0 = time.perf_counter()
        while self.page.locator("#lesson-step-title").inner_text() == title and time.perf_counter() - t0 < 10:
            self.page.wait_for_timeout(100)

    def lesson(self, n: int):
        sel = self.page.locator(".lesson-select select")
        sel.select_option(label=sel.locator("option", has_text=f"{n}. ").first.inner_text())
        self.page.locator("#lesson-step-title", has_text="Step 1.").wait_for()
        self.page.locator("#lesson-progress", has_text=f"of {len(LESSONS[n - 1].steps)} answered").wait_for()


@pytest.mark.timeout(600)
def test_five_lessons_end_to_end(lessons_server):
    SHOTS.mkdir(parents=True, exist_ok=True)
    timings = {}
    with context(1280, 720, timeout_ms=20_000) as ctx:
        page = ctx.new_page()
        errors = []
        page.on("pageerror", lambda exc: errors.append(str(exc)))
        s = Student(page)
        t0 = time.perf_counter()
        try:
            # permalink straight to lesson 1, step 2
            page.goto(lessons_server + "?lesson=1&step=2", timeout=90_000)
            page.locator("#lesson-step-title", has_text="Step 2. How fast").wait_for(timeout=60_000)
            timings["load"] = time.perf_counter() - t0
            page.locator(".lesson-prev button").click()
            page.locator("#lesson-step-title", has_text="Step 1.").wait_for()

            # ---- lesson 1: linear theory
            s.set_up("Linear theory")
            page.locator("#linear-model", has_text="tau15, non-isothermal").wait_for()
            lam = number(s.card("ro-lambda-max"))
            s.expect(lam * 1.5, "wrong")
            s.expect(lam, "correct")
            s.shot("L1S1")
            s.next()
            s.set_up("Linear theory")
            efold = number(s.card_note("ro-max-growth"))  # "e-folds in 3.87 orbits"
            s.expect(efold, "wrong")  # the card's number is not the answer: tenfold is ln 10 e-folds
            s.expect(efold * math.log(10), "correct")
            s.shot("L1S2")
            s.next()
            s.set_up("Linear theory")
            page.locator("#ro-q0 .ro-value", has_text="1.14").wait_for()  # sigma0 = 700
            lz = number(s.card("ro-lambda-zero"))
            s.expect(lz * 0.7, "wrong")
            s.expect(lz, "correct")
            s.shot("L1S3")
            s.next()
            s.set_up("Linear theory")
            page.locator("#ro-q0 .ro-value", has_text="2.00").wait_for()
            bc = number(s.card("ro-beta-c"))
            s.expect(bc + 0.3, "wrong")
            s.expect(bc, "correct")
            page.locator("#lesson-progress", has_text="4 of 4 answered").wait_for()
            s.shot("L1S4")
            timings["lesson1"] = time.perf_counter() - t0

            # ---- lesson 2: white noise without self-gravity
            s.lesson(2)
            s.set_up("Hydrodynamics")
            page.locator("#hydro-run-label", has_text="isothermal, σ₀ = 0 kg/m²").wait_for()
            s.paused_by_lesson("hydro")
            page.locator(".bk-tab", has_text="Linear theory").click()
            g_lin = number(s.card("ro-max-growth"))
            page.locator(".bk-tab", has_text="Hydrodynamics").click()
            s.expect(3 * g_lin, "wrong")
            s.expect(round(0.85 * g_lin, 4), "correct")
            s.shot("L2S1")
            s.next()
            s.set_up("Hydrodynamics")  # the same run goes on for 50 orbits
            s.paused_by_lesson("hydro")
            assert s.wait_orbits("hydro-orbits", 150) < 160
            lp = number(s.card("hydro-lambda-p"))
            s.expect(2.5 * lp, "wrong")
            s.expect(lp, "correct")
            s.shot("L2S2")
            s.next()
            s.set_up("Hydrodynamics")
            s.paused_by_lesson("hydro")
            s.expect("sinks", "wrong", choice=True)
            s.expect("sources", "correct", choice=True)
            s.shot("L2S3")
            timings["lesson2"] = time.perf_counter() - t0

            # ---- lesson 3: self-gravity picks the wavelength
            s.lesson(3)
            s.set_up("Hydrodynamics")
            page.locator("#hydro-run-label", has_text="non-isothermal, σ₀ = 0 kg/m²").wait_for()
            s.paused_by_lesson("hydro")  # 220 orbits: saturated without self-gravity too
            lp0 = number(s.card("hydro-lambda-p"))
            s.expect(lp0 * 3, "wrong")
            s.expect(lp0, "correct")
            s.shot("L3S1")
            s.next()
            s.set_up("Hydrodynamics")
            page.locator("#hydro-run-label", has_text="σ₀ = 400 kg/m²").wait_for()
            s.paused_by_lesson("hydro")
            lp = number(s.card("hydro-lambda-p"))
            s.expect(lp * 0.5, "wrong")
            text = s.expect(lp, "correct")
            assert "1.4 λ_zero" in text
            s.shot("L3S2")
            s.next()
            s.set_up("Linear theory")
            page.locator("#ro-q0 .ro-value", has_text="1.14").wait_for()  # sigma0 = 700 (the preset linear-700)
            lz = number(s.card("ro-lambda-zero"))
            s.expect(lz, "wrong")  # lambda_zero itself is not the saturated wavelength
            s.expect(round(1.4 * lz, 1), "correct")
            s.shot("L3S3")
            timings["lesson3"] = time.perf_counter() - t0

            # ---- lesson 4: particles instead of a fluid
            s.lesson(4)
            s.set_up("N-body")
            page.locator("#nbody-run-label", has_text="σ₀ = 0 kg/m²").wait_for()
            s.paused_by_lesson("nbody")  # 6 orbits: one 5-orbit transport window
            ceff = number(s.card("nbody-ceff"))
            c_mean = number(s.card("nbody-c"))
            s.expect(c_mean, "wrong")  # the random velocity <c> is not c_eff
            s.expect(ceff, "correct")
            s.shot("L4S1")
            s.next()
            s.set_up("N-body")  # the box stays paused
            page.locator("#nbody-status", has_text="Paused").wait_for()
            nu = number(s.card("nbody-nu"))
            s.expect(2 * nu, "wrong")
            s.expect(nu, "correct")
            s.shot("L4S2")
            s.next()
            s.set_up("N-body")
            s.expect("local (carried", "wrong", choice=True)
            s.expect("nonlocal (passed", "correct", choice=True)
            s.shot("L4S3")
            timings["lesson4"] = time.perf_counter() - t0

            # ---- lesson 5: buffer zone
            s.lesson(5)
            s.set_up("Hydrodynamics")
            page.locator("#hydro-buffer .ro-value", has_text="β = -0.5").wait_for()
            s.paused_by_lesson("hydro")
            s.expect("outside the buffer zone", "wrong", choice=True)
            s.expect("inside the buffer zone", "correct", choice=True)
            s.shot("L5S1")
            s.next()
            s.set_up("Hydrodynamics")
            s.paused_by_lesson("hydro")
            s.expect("a source", "wrong", choice=True)
            s.expect("a sink", "correct", choice=True)
            s.shot("L5S2")
            timings["lesson5"] = time.perf_counter() - t0

            # glossary and worksheet are reachable
            page.locator(".lessons-panel .bk-tab", has_text="Glossary").click()
            page.locator("#gloss-lambda_zero").wait_for()
            page.screenshot(path=str(SHOTS / "glossary.png"))
            page.locator(".lessons-panel .bk-tab", has_text="Lessons").click()
            with ctx.expect_page() as popup:
                page.locator(".lesson-worksheet button").click()
            ws = popup.value
            ws.wait_for_load_state()
            assert "Lesson 5: A buffer zone" in ws.locator("h1").inner_text()
            ws.set_viewport_size({"width": 1280, "height": 720})
            ws.screenshot(path=str(SHOTS / "worksheet5.png"), full_page=True)
            for les in LESSONS:  # every worksheet prints on one A4 page
                ws.goto(worksheet_path(les.number).resolve().as_uri())
                pdf = ws.pdf(format="A4", prefer_css_page_size=True)
                assert len(re.findall(rb"/Type\s*/Page[^s]", pdf)) == 1, f"worksheet {les.number} > 1 page"
        except Exception:
            page.screenshot(path=str(SHOTS / "failure.png"))
            raise
        finally:
            timings["total"] = time.perf_counter() - t0
            print("timings [s]:", {k: round(v, 1) for k, v in timings.items()})
    assert not errors, f"JavaScript errors: {errors}"
