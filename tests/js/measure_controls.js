// Measures every visible control of the dashboard page (run by tests/test_browser_layout.py).
// Returns a list of problems: a control cut off, outside the window or the app's box, squeezed to
// nothing, hidden by an ancestor that clips it, a list row wider than its list, a touch target too
// small; and whether the document scrolls sideways.
(args) => {
  const { minTouch, appSelector } = args;
  const problems = [];
  const docWidth = document.documentElement.clientWidth;
  const app = document.querySelector(appSelector);
  const appBox = app ? app.getBoundingClientRect() : null;
  const selectors = [
    "button", "input:not([type=hidden]):not([type=file])", "select", "textarea",
    ".widget-slider", ".widget-toggle-button",
  ];
  const seen = new Set();
  const controls = [];
  for (const el of document.querySelectorAll(selectors.join(","))) {
    if (seen.has(el) || !app || !app.contains(el)) continue;
    seen.add(el);
    const style = getComputedStyle(el);
    if (el.getClientRects().length === 0 || style.visibility === "hidden") continue; // not shown
    controls.push(el);
  }
  const describe = (el) => {
    const cls = [...el.classList].filter((c) => c.startsWith("pmk-")).join(".");
    const owner = el.closest("[class*='pmk-']");
    const ownerCls = owner ? [...owner.classList].filter((c) => c.startsWith("pmk-")).join(".") : "";
    const text = (el.innerText || el.value || el.getAttribute("title") || "").trim().slice(0, 40);
    return `${el.tagName.toLowerCase()}${cls ? "." + cls : ""} in .${ownerCls} "${text}"`;
  };
  const canvas = document.createElement("canvas").getContext("2d");
  for (const el of controls) {
    const r = el.getBoundingClientRect();
    const name = describe(el);
    if (r.width < 1 || r.height < 1) {
      problems.push(`${name}: squeezed to ${r.width.toFixed(0)}x${r.height.toFixed(0)} px`);
      continue;
    }
    if (r.left < -0.5 || r.right > docWidth + 0.5) {
      problems.push(`${name}: outside the window (x ${r.left.toFixed(0)}..${r.right.toFixed(0)}, width ${docWidth})`);
    }
    if (appBox && (r.left < appBox.left - 0.5 || r.right > appBox.right + 0.5)) {
      problems.push(`${name}: outside the app's box (x ${r.left.toFixed(0)}..${r.right.toFixed(0)}, ` +
        `app ${appBox.left.toFixed(0)}..${appBox.right.toFixed(0)})`);
    }
    const tag = el.tagName.toLowerCase();
    if (tag === "button" && el.scrollWidth > el.clientWidth + 1) {
      problems.push(`${name}: text cut off (${el.scrollWidth} px of text in ${el.clientWidth} px)`);
    }
    if ((tag === "input" || tag === "textarea") && r.width < 80) {
      problems.push(`${name}: too narrow to type in (${r.width.toFixed(0)} px)`);
    }
    if (tag === "select") {
      const st = getComputedStyle(el);
      canvas.font = `${st.fontWeight} ${st.fontSize} ${st.fontFamily}`;
      const pad = parseFloat(st.paddingLeft) + parseFloat(st.paddingRight);
      const arrow = el.size > 1 || el.multiple ? 0 : 24; // a dropdown keeps room for its arrow
      const rows = el.size > 1 || el.multiple ? [...el.options] : [...el.selectedOptions];
      for (const opt of rows) {
        const optPad = parseFloat(getComputedStyle(opt).paddingLeft || "0") * 2;
        const need = canvas.measureText(opt.text).width + pad + optPad + arrow;
        if (need > el.clientWidth + 1) {
          problems.push(`${name}: row "${opt.text}" cut off (${need.toFixed(0)} px in ${el.clientWidth} px)`);
        }
      }
    }
    // an ancestor that clips (overflow other than visible) must contain the control
    for (let p = el.parentElement; p && p !== document.body; p = p.parentElement) {
      const ov = getComputedStyle(p);
      if (ov.overflowX === "visible" && ov.overflowY === "visible") continue;
      const pr = p.getBoundingClientRect();
      if (r.right > pr.right + 1 || r.left < pr.left - 1) {
        const pc = [...p.classList].slice(0, 3).join(".");
        problems.push(`${name}: cut off by .${pc} (x ${r.left.toFixed(0)}..${r.right.toFixed(0)} ` +
          `in ${pr.left.toFixed(0)}..${pr.right.toFixed(0)})`);
        break;
      }
    }
    if (minTouch && (tag === "button" || tag === "select" || (tag === "input" && el.type !== "checkbox"))) {
      if (r.height < minTouch - 0.5 || r.width < minTouch - 0.5) {
        problems.push(`${name}: touch target ${r.width.toFixed(0)}x${r.height.toFixed(0)} px < ${minTouch} px`);
      }
    }
    if (minTouch && tag === "input" && el.type === "checkbox") {
      const label = el.closest(".widget-checkbox") || el;
      const lr = label.getBoundingClientRect();
      if (lr.height < minTouch - 0.5) {
        problems.push(`${name}: checkbox row ${lr.height.toFixed(0)} px high < ${minTouch} px`);
      }
    }
  }
  const root = document.scrollingElement || document.documentElement;
  return {
    problems,
    controls: controls.length,
    horizontalScroll: root.scrollWidth > root.clientWidth + 1,
    scrollWidth: root.scrollWidth,
    clientWidth: root.clientWidth,
    appWidth: appBox ? appBox.width : 0,
  };
}
