// spl configure: the page's behaviour (docs/configure.md). Vendored, no build step.
// Every control is a native button, input or select, so it is keyboard-operable; a
// decision is answered with the rows whose state changed, which are patched in place.
(function () {
  "use strict";
  const rows = new Map();
  document.querySelectorAll("[data-feature]").forEach((row) => rows.set(row.dataset.feature, row));
  const products = document.querySelector("[data-products]");
  const complete = document.querySelector("[data-complete]");
  const explanation = document.querySelector("[data-explanation]");
  const architecture = document.querySelector("[data-architecture]");
  const bundle = document.querySelector('a[data-action="bundle"]');
  const warnings = document.querySelector("[data-warnings]");
  const message = document.querySelector("[data-message]");
  const countButton = document.querySelector('[data-action="count"]');
  const analysisOnly = document.body.dataset.analysisOnly === "true";
  let generation = 0; // the view's version: late answers for older views are dropped
  let focused = null;
  // click-to-page and server milliseconds of each decision (bench/configure_latency.py)
  window.splConfigure = { timings: [], server: [], pending: 0 };

  async function call(method, url, body) {
    window.splConfigure.pending += 1;
    try {
      const response = await fetch(url, {
        method: method,
        headers: body === undefined ? {} : { "Content-Type": "application/json" },
        body: body === undefined ? undefined : JSON.stringify(body),
        credentials: "same-origin",
      });
      const data = await response.json().catch(() => ({}));
      const timing = /dur=([0-9.]+)/.exec(response.headers.get("Server-Timing") || "");
      return { status: response.status, data: data, server: timing ? Number(timing[1]) : null };
    } finally {
      window.splConfigure.pending -= 1;
    }
  }

  function say(text) {
    message.textContent = text;
  }

  function apply(view) {
    generation += 1;
    for (const [name, state] of Object.entries(view.states)) {
      const row = rows.get(name);
      if (row) mark(row, name, state);
    }
    showCount(view.products);
    complete.textContent = view.complete ? "complete: the selection resolves" : "open choices remain";
    document.querySelector('[data-action="undo"]').disabled = !view.undo;
    document.querySelector('[data-action="redo"]').disabled = !view.redo;
    document.querySelectorAll("[data-attribute]").forEach((input) => {
      if (document.activeElement !== input) input.value = view.attributes[input.dataset.attribute] || "";
    });
    document.querySelectorAll("[data-sharing]").forEach((select) => {
      const mode = view.sharing[select.dataset.sharing];
      const fallback = Array.from(select.options).find((o) => o.text.endsWith("(default)"));
      select.value = mode || (fallback ? fallback.value : select.value);
    });
    document.querySelectorAll("[data-deployment]").forEach((input) => {
      const settings = view.deployment[input.dataset.deployment] || {};
      if (document.activeElement !== input) input.value = settings[input.dataset.key] || "";
    });
    if (!view.products.exact) exactCount(generation, false);
    if (focused && view.states[focused] !== undefined) explain(focused);
    if (!analysisOnly) drawArchitecture(view.complete, generation);
  }

  // A decision against an implied value would leave no product: its control says so
  // (aria-disabled keeps it focusable; pressing it shows the reason from the server).
  function mark(row, name, state) {
    row.dataset.state = state;
    row.querySelector('[data-action="explain"]').setAttribute("aria-label", "why " + name + " is " + state);
    const against = { "implied-selected": "deselect", "implied-deselected": "select" }[state];
    for (const action of ["select", "deselect"]) {
      const button = row.querySelector('[data-action="' + action + '"]');
      if (action === against) {
        button.setAttribute("aria-disabled", "true");
        button.title = action + " " + name + ": no product would be left (choose " + name + " to see why)";
      } else {
        button.removeAttribute("aria-disabled");
        button.removeAttribute("title");
      }
    }
  }
  rows.forEach((row, name) => mark(row, name, row.dataset.state));

  function showCount(count) {
    products.textContent = count.text;
    products.dataset.exact = count.exact ? "true" : "false";
    countButton.hidden = count.exact;
  }

  async function exactCount(version, exhaustive) {
    if (exhaustive) products.textContent = "counting…";
    const { status, data } = await call("GET", "/api/count" + (exhaustive ? "?exhaustive=true" : ""));
    if (status === 200 && version === generation) showCount(data.products);
  }

  async function drawArchitecture(isComplete, version) {
    if (!isComplete) {
      bundle.hidden = true;
      architecture.innerHTML = "<p>Complete the selection to see the architecture it builds.</p>";
      warnings.innerHTML = "";
      return;
    }
    architecture.innerHTML = "<p>Resolving…</p>";
    const { status, data } = await call("GET", "/api/architecture");
    if (version !== generation) return;
    if (status !== 200) {
      architecture.textContent = (data.explanation || [data.error]).join("\n");
      return;
    }
    architecture.innerHTML = data.svg;
    warnings.innerHTML = "";
    for (const text of data.warnings) {
      const item = document.createElement("li");
      item.textContent = text;
      warnings.appendChild(item);
    }
    bundle.hidden = false;
    bundle.setAttribute("download", data.product + ".zip");
  }

  async function explain(name) {
    focused = name;
    const { data } = await call("GET", "/api/explain?feature=" + encodeURIComponent(name));
    if (focused === name) explanation.textContent = (data.lines || [data.error]).join("\n");
  }

  async function decide(name, action, started) {
    const { status, data, server } = await call("POST", "/api/decide", { feature: name, action: action });
    window.splConfigure.server.push(server);
    if (status === 200) {
      say("");
      apply(data);
    } else {
      // refused: the selection is unchanged; the reason goes where the user looks
      const reason = (data.explanation || [data.error]).join("\n");
      say(name + ": " + action + " refused: " + reason);
      explanation.textContent = action + " " + name + " is impossible:\n" + reason;
    }
    requestAnimationFrame(() => window.splConfigure.timings.push(performance.now() - started));
  }

  async function change(url, body, errorTarget) {
    const { status, data } = await call("POST", url, body);
    if (errorTarget) errorTarget.textContent = status === 200 ? "" : data.error;
    if (status === 200) {
      say("");
      apply(data);
    } else if (!errorTarget) {
      say(data.error);
    }
    return status;
  }

  document.querySelector("[data-tree]").addEventListener("click", (event) => {
    const button = event.target.closest("button[data-action]");
    if (!button) return;
    const name = button.closest("[data-feature]").dataset.feature;
    if (button.dataset.action === "explain") explain(name);
    else decide(name, button.dataset.action, performance.now());
  });
  document.querySelector("[data-tree]").addEventListener("focusin", (event) => {
    const button = event.target.closest('button[data-action="explain"]');
    if (button) explain(button.closest("[data-feature]").dataset.feature);
  });
  document.querySelectorAll("[data-attribute]").forEach((input) => {
    input.addEventListener("change", () => {
      const target = document.querySelector('[data-error-for="' + input.dataset.attribute + '"]');
      change("/api/attribute", { key: input.dataset.attribute, value: input.value }, target);
    });
  });
  document.querySelectorAll("[data-sharing]").forEach((select) => {
    select.addEventListener("change", () => change("/api/sharing", { feature: select.dataset.sharing, mode: select.value }));
  });
  document.querySelectorAll("[data-deployment]").forEach((input) => {
    input.addEventListener("change", () => {
      const key = "deployment:" + input.dataset.deployment + "." + input.dataset.key;
      const target = document.querySelector('[data-error-for="' + key + '"]');
      change("/api/deployment", { container: input.dataset.deployment, key: input.dataset.key, value: input.value }, target);
    });
  });
  countButton.addEventListener("click", () => exactCount(generation, true));
  document.querySelector('[data-action="undo"]').addEventListener("click", () => change("/api/undo", {}));
  document.querySelector('[data-action="redo"]').addEventListener("click", () => change("/api/redo", {}));

  function upload(selector, url) {
    const input = document.querySelector(selector);
    if (!input) return;
    input.addEventListener("change", async () => {
      const file = input.files[0];
      if (!file) return;
      const text = await file.text();
      const status = await change(url, { text: text, filename: file.name });
      if (status === 200) say("imported " + file.name);
      input.value = "";
    });
  }
  upload('[data-action="import"]', "/api/selection");
  upload('[data-action="capabilities"]', "/api/capabilities");

  const save = document.querySelector('[data-action="save"]');
  if (save) {
    save.addEventListener("click", async () => {
      const name = document.querySelector("[data-save-name]").value.trim();
      const { status, data } = await call("POST", "/api/save", { name: name });
      say(status === 200 ? "saved " + data.saved : data.error);
    });
  }
  if (!analysisOnly && document.querySelector("[data-complete]").textContent.startsWith("complete")) {
    drawArchitecture(true, generation);
  }
  if (products.dataset.exact === "false") exactCount(generation, false);
})();
