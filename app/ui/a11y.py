"""Access for keyboards, screen readers and low-contrast projectors: what Bokeh's widgets lack, added by the page.

* :data:`BUTTON_CSS` / :func:`button`: Bokeh's green, orange and red buttons carry white 12 px text at a contrast
  of 2.5 (green) and less; WCAG asks 4.5.  These colours keep the meaning and reach 5 or more.
* :data:`PAGE_SCRIPT` (put in the page's HTML by ``ringlab.main``, inline: nothing is loaded from elsewhere):

  - the tabs of every ``pn.Tabs`` (Bokeh's tab headers are plain ``div`` elements, not reachable by Tab and
    deaf to keys) become ARIA tabs: one Tab stop per tab bar (the active tab), Left/Right arrows (Home/End)
    move to the neighbouring tab and open it, Enter and Space open the focused tab; the tab bar comes before the
    tabs' content in the page (Bokeh puts it after, and draws it above), so the keyboard reaches the tab bar,
    then the open tab's controls, then its plot toolbars;
  - slider handles (noUiSlider) get the slider's title as their name, a checkbox without a label its text, the
    arrow buttons of a number box "Increase"/"Decrease" and the box's label, a file input its hidden label's text;
  - a settings file (the file input of class ``settings-upload``) over :data:`UPLOAD_LIMIT_BYTES` is refused
    in the browser with a message, before anything is sent;
  - a "Skip to the lesson" link, the page's first Tab stop, moves the focus to the lesson's answer box
    (or its title);
  - where the lessons panel is not beside the tabs (a phone: it starts several screens down), a "Lesson" button
    fixed at the foot of the window scrolls the step's question into view (and then reads "Back to the run").

  Bokeh draws every widget in a shadow root, which the page's own observers do not see: the script walks the
  page's shadow roots once a second and fixes what is new (its cost per walk is not measured yet).
"""
from __future__ import annotations

import panel as pn

BUTTON_CSS = """
:host .bk-btn-success {background-color: #1e7b34; border-color: #19692c; color: #fff;}
:host .bk-btn-success:hover {background-color: #19692c;}
:host .bk-btn-warning {background-color: #8a4b00; border-color: #7a4200; color: #fff;}
:host .bk-btn-warning:hover {background-color: #7a4200;}
:host .bk-btn-danger {background-color: #b02a37; border-color: #9a2430; color: #fff;}
:host .bk-btn-danger:hover {background-color: #9a2430;}
"""


def button(**params) -> pn.widgets.Button:
    """A ``pn.widgets.Button`` whose colours (``color``) have a text contrast of 4.5 or more (see module)."""
    params["stylesheets"] = [BUTTON_CSS, *params.get("stylesheets", [])]
    return pn.widgets.Button(**params)


UPLOAD_LIMIT_BYTES = 64 * 1024  # [bytes] a settings upload refused in the browser above this (the server's limit)
SKIP_CSS = (".rl-skip {position: absolute; left: -10000px; top: 4px; z-index: 1000; background: #fff; color: #1f4e79;"
            " padding: 6px 12px; border: 2px solid #1f4e79; font: 16px system-ui, sans-serif;}"
            " .rl-skip:focus {left: 8px;}")

# the phone's "Lesson" button: fixed at the foot of the window, at the left (plot toolbars are at the right)
JUMP_CSS = (".rl-lesson-jump {position: fixed; left: 10px; bottom: 10px; z-index: 1000; background: #1f4e79;"
            " color: #fff; border: 2px solid #fff; border-radius: 20px; padding: 8px 16px; min-height: 44px;"
            " font: 600 16px system-ui, sans-serif; box-shadow: 0 2px 6px rgba(0,0,0,.35); cursor: pointer;}"
            " .rl-lesson-jump:focus-visible {outline: 3px solid #ffbf47; outline-offset: 2px;}"
            " .rl-lesson-jump[hidden] {display: none;}"
            # while it is shown: the page ends clear of it, and an element reached by Tab is scrolled above it
            " html.rl-jump-shown {scroll-padding-bottom: 72px;} html.rl-jump-shown body {padding-bottom: 72px;}")

PAGE_SCRIPT = r"""
(function () {
  function roots(root, out) {
    out.push(root);
    for (const el of root.querySelectorAll("*")) if (el.shadowRoot) roots(el.shadowRoot, out);
    return out;
  }
  function find(sel) {
    for (const r of roots(document, [])) { const el = r.querySelector(sel); if (el) return el; }
    return null;
  }
  // Bokeh puts a tab bar after the tabs' content in its shadow root (drawn above it by a CSS grid area), and a
  // tab built later is appended after it again: the keyboard reached every control and plot toolbar of the open
  // tab before the tab bar.  The bar goes first, at once after every change of the root's children (moveBefore
  // keeps the focus of a tab header the student is on; insertBefore where it does not exist loses it).
  const watched = new WeakSet();
  function bar(root) {  // the tab bar of a Tabs' shadow root (":scope" matches nothing in a shadow root)
    for (const el of root.children) if (el.classList.contains("bk-header") && el.querySelector(".bk-headers-wrapper")) return el;
    return null;
  }
  function barFirst(root) {
    const header = bar(root);
    if (!header) return;
    let first = root.firstElementChild;
    while (first && (first.tagName === "STYLE" || first.tagName === "LINK")) first = first.nextElementSibling;
    if (!first || first === header) return;
    if (root.moveBefore) { try { root.moveBefore(header, first); return; } catch (err) { /* fall through */ } }
    root.insertBefore(header, first);
  }
  function fixTabs(r) {
    if (r.host && bar(r)) {
      barFirst(r);
      if (!watched.has(r)) { watched.add(r); new MutationObserver(function () { barFirst(r); }).observe(r, {childList: true}); }
    }
    for (const bar of r.querySelectorAll(".bk-headers-wrapper")) {
      bar.setAttribute("role", "tablist");
      for (const tab of bar.querySelectorAll(".bk-tab")) {
        const active = tab.classList.contains("bk-active");
        tab.setAttribute("role", "tab");
        tab.setAttribute("aria-selected", active ? "true" : "false");
        tab.setAttribute("tabindex", active ? "0" : "-1");
      }
    }
  }
  function fixNames(r) {
    for (const h of r.querySelectorAll("[role=slider]:not([aria-label])")) {
      const title = r.querySelector(".bk-slider-title");
      const text = title ? title.textContent.split(":")[0].trim() : "";
      h.setAttribute("aria-label", text || "value");
    }
    for (const b of r.querySelectorAll(".bk-spin-btn:not([aria-label])")) {  // a number box's arrow buttons
      const label = r.querySelector("label");
      const what = label ? " " + label.textContent.trim() : "";
      b.setAttribute("aria-label", (b.classList.contains("bk-spin-btn-up") ? "Increase" : "Decrease") + what);
    }
    for (const f of r.querySelectorAll("input[type=file]:not([aria-label])")) {  // its label is drawn hidden
      const label = f.labels && f.labels.length ? f.labels[0].textContent.trim() : "";
      f.setAttribute("aria-label", label || "Choose a file");
    }
    for (const box of r.querySelectorAll("input[type=checkbox]:not([aria-label])")) {
      if (box.closest("label") && box.closest("label").textContent.trim()) continue;
      const next = box.nextElementSibling;  // Bokeh's checkbox: <input> and a <div class="bk-label"> beside it
      const text = ((next && next.classList.contains("bk-label")) ? next.textContent :
                    (box.parentElement ? box.parentElement.textContent : "")).trim();
      if (text) box.setAttribute("aria-label", text);
    }
  }
  // a settings file over the limit is refused here, before Bokeh's file input reads it and sends it over the
  // websocket as one message (50 MB went over the server's 20 MB limit: the page died without a word)
  function refuse(e) {
    const input = e.currentTarget, file = input.files && input.files[0];
    if (!file || file.size <= UPLOAD_LIMIT) return;
    e.stopImmediatePropagation();
    input.value = "";
    const root = input.getRootNode();
    let msg = root.querySelector(".upload-refused");
    if (!msg) {
      msg = document.createElement("div");
      msg.className = "upload-refused"; msg.setAttribute("role", "alert");
      msg.style.cssText = "color:#8a0015;font-size:14px;margin-top:4px;white-space:normal;max-width:100%;width:100%";
      input.insertAdjacentElement("afterend", msg);
    }
    msg.textContent = file.name + " has " + file.size + " bytes: a settings file has at most " + UPLOAD_LIMIT +
      " (one saved by this page has about 1 KiB); nothing was sent.";
  }
  function guardUploads(r) {
    if (!r.host || !r.host.classList.contains("settings-upload")) return;
    for (const input of r.querySelectorAll("input[type=file]:not([data-rl-limit])")) {
      input.setAttribute("data-rl-limit", String(UPLOAD_LIMIT));
      input.addEventListener("change", refuse, true);  // before Bokeh's own listener on the same element
    }
  }
  function fix() { for (const r of roots(document, [])) { fixTabs(r); fixNames(r); guardUploads(r); } }
  // Bokeh draws the tab bar again when the open tab changes (once the tab's content arrives from the server):
  // until then, and for a few seconds, a lost focus goes back to the header of the tab opened from the keyboard
  let pending = null;
  function deepFocus() {
    let el = document.activeElement;
    while (el && el.shadowRoot && el.shadowRoot.activeElement) el = el.shadowRoot.activeElement;
    return el;
  }
  function refocus() {
    if (!pending || Date.now() > pending.until) { pending = null; return; }
    const el = deepFocus();
    if (el && el !== document.body && !el.shadowRoot) return;  // the focus is somewhere: leave it there
    const now = pending.root.querySelectorAll(".bk-tab")[pending.index];
    if (now && now.isConnected) { fixTabs(pending.root); now.focus(); }
  }
  function open(tab) {
    const root = tab.getRootNode();
    pending = {root: root, index: Array.from(root.querySelectorAll(".bk-tab")).indexOf(tab), until: Date.now() + 8000};
    tab.click();
    tab.focus();
  }
  setInterval(refocus, 100);
  document.addEventListener("keydown", function (e) {
    const el = e.composedPath()[0];
    if (!el || !el.classList || !el.classList.contains("bk-tab")) return;
    const tabs = Array.from(el.parentElement.querySelectorAll(".bk-tab"));
    const i = tabs.indexOf(el);
    let to = null;
    if (e.key === "Enter" || e.key === " ") to = el;
    else if (e.key === "ArrowRight" || e.key === "ArrowDown") to = tabs[(i + 1) % tabs.length];
    else if (e.key === "ArrowLeft" || e.key === "ArrowUp") to = tabs[(i - 1 + tabs.length) % tabs.length];
    else if (e.key === "Home") to = tabs[0];
    else if (e.key === "End") to = tabs[tabs.length - 1];
    if (to) { e.preventDefault(); open(to); }
  }, true);
  function skipLink() {
    if (document.querySelector(".rl-skip")) return;
    const style = document.createElement("style");
    style.textContent = SKIP_CSS;
    document.head.appendChild(style);
    const a = document.createElement("a");
    a.className = "rl-skip"; a.href = "#lesson"; a.textContent = "Skip to the lesson";
    a.addEventListener("click", function (e) {
      e.preventDefault();
      const host = find(".lesson-answer");  // the answer box lives in its widget's shadow root
      const input = host && host.shadowRoot ? host.shadowRoot.querySelector("input") : null;
      const box = (input && input.offsetParent !== null) ? input : find("#lesson-step-title");
      if (!box) return;
      if (!box.hasAttribute("tabindex") && box.tagName !== "INPUT") box.setAttribute("tabindex", "-1");
      box.scrollIntoView({block: "center"}); box.focus();
    });
    document.body.insertBefore(a, document.body.firstChild);
  }
  // a phone (no lessons panel beside the tabs: it starts screens below the run): a button fixed at the foot of
  // the window jumps to the lesson's question, and once there back to the tab bar
  let jump = null;
  function jumpButton() {
    if (jump) return;
    const style = document.createElement("style");
    style.textContent = JUMP_CSS;
    document.head.appendChild(style);
    jump = document.createElement("button");
    jump.type = "button"; jump.className = "rl-lesson-jump"; jump.hidden = true;
    jump.addEventListener("click", function () {
      if (jump.dataset.to === "run") {
        const tab = find(".bk-tab.bk-active");
        const top = find("#app-header");
        if (top) top.scrollIntoView({block: "start"});
        if (tab) tab.focus({preventScroll: true});
      } else {
        const title = find("#lesson-step-title"), question = find("#lesson-question");
        if (!title) return;
        title.style.scrollMarginTop = "8px";
        title.scrollIntoView({block: "start"});
        if (question && question.getBoundingClientRect().bottom > innerHeight)
          question.scrollIntoView({block: "end"});  // a long step text: the question in view, its title above
        if (!title.hasAttribute("tabindex")) title.setAttribute("tabindex", "-1");
        title.focus({preventScroll: true});  // not the answer box: it would open a phone's keyboard over the step
      }
      placeJump();
    });
    const skip = document.querySelector(".rl-skip");
    document.body.insertBefore(jump, skip ? skip.nextSibling : document.body.firstChild);
    addEventListener("scroll", placeJump, {passive: true});
    addEventListener("resize", placeJump);
  }
  let side = null, title = null;  // found once (a walk of every shadow root), again when drawn anew
  function placeJump() {
    if (!jump) return;
    if (!side || !side.isConnected) side = find(".side-panel");
    if (!title || !title.isConnected) title = find("#lesson-step-title");
    const beside = side && side.getBoundingClientRect().left > 100;  // the lessons panel beside the tabs
    jump.hidden = !title || !title.getClientRects().length || !side || beside;
    document.documentElement.classList.toggle("rl-jump-shown", !jump.hidden);
    if (jump.hidden) return;
    const there = title.getBoundingClientRect().top < innerHeight;  // the lesson is on screen
    jump.dataset.to = there ? "run" : "lesson";
    const label = there ? "Back to the run" : "Lesson";
    if (jump.dataset.label === label) return;
    const arrow = document.createElement("span");  // the arrow is drawn, not read
    arrow.setAttribute("aria-hidden", "true"); arrow.textContent = there ? " \u25B2" : " \u25BC";
    jump.dataset.label = label;
    jump.replaceChildren(document.createTextNode(label), arrow);
  }
  function start() { skipLink(); jumpButton(); fix(); placeJump(); setInterval(function () { fix(); placeJump(); }, 1000); }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start); else start();
})();
""".replace("SKIP_CSS", repr(SKIP_CSS)).replace("JUMP_CSS", repr(JUMP_CSS)).replace("UPLOAD_LIMIT", str(UPLOAD_LIMIT_BYTES))


def page_script_html() -> str:
    """The ``<script>`` element of :data:`PAGE_SCRIPT` for the page template."""
    return f"<script>{PAGE_SCRIPT}</script>"


def page_template() -> str:
    """A block of Panel's page template (``doc.template``): the page laid out for the device's width (a phone gets
    the one-column layout, not a shrunk desktop page) and :data:`PAGE_SCRIPT`."""
    return ('{% block postamble %}<meta name="viewport" content="width=device-width, initial-scale=1">'
            + page_script_html() + '{% endblock %}')
