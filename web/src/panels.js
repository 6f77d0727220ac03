// The parameter panels, generated from the style schema (GET /api/schema): one panel per
// modelling step, one control per field with its unit, range and documentation, and the
// server's validation message shown beside the control.

const panelTitles = {
  style: "Style", head: "Head", counts: "Counts (§2.3)", maps: "Scalp maps (§2.3)",
  growth: "Growth", strand: "Strand", prototype: "Prototype (§2.2)", wisp: "Wisp l(u), r(s), σ (§2.1)",
  clump: "Clumps", hairline: "Hairline", flyaway: "Flyaways",
  colour: "Colour (§5)", solver: "Solver κ, τ (§3)", "styling field": "Styling field Φ (§3.1)",
  cut: "Cut (§6.2)", constraints: "Constraints (§4)", dynamics: "Dynamics (AWT)",
};
const openPanels = new Set(["counts", "maps", "prototype", "wisp", "colour", "solver"]);

function label(field) {
  const key = field.path.split(".").pop();
  return field.unit ? `${key} (${field.unit})` : key;
}

// A slider's step: about a thousandth of the range.
function step(field) {
  if (field.type === "integer") return 1;
  const span = field.max - field.min;
  return span > 0 ? Math.pow(10, Math.floor(Math.log10(span)) - 3) : 0.001;
}

export class Panels {
  // onChange(path, value, { final }): a control moved (final: it was released).
  constructor(element, schema, onChange) {
    this.element = element;
    this.controls = new Map();  // path → { set(value), error(message) }
    this.onChange = onChange;
    for (const panel of schema.panels) {
      const fields = schema.fields.filter((f) => f.panel === panel && f.type !== "groups");
      if (!fields.length) continue;
      const details = document.createElement("details");
      details.open = openPanels.has(panel);
      details.className = "panel";
      const summary = document.createElement("summary");
      summary.textContent = panelTitles[panel] ?? panel;
      details.append(summary);
      for (const field of fields) details.append(this.control(field));
      element.append(details);
    }
  }

  control(field) {
    const row = document.createElement("div");
    row.className = "field";
    row.title = `${field.path}: ${field.doc}${field.paper ? ` (${field.paper})` : ""}`;
    const name = document.createElement("label");
    name.textContent = label(field);
    const message = document.createElement("div");
    message.className = "message";
    row.append(name);
    const send = (value, final) => this.onChange(field.path, value, { final });
    let set;
    const finite = Number.isFinite(field.min) && Number.isFinite(field.max) && field.max - field.min <= 1e4;
    if ((field.type === "number" || field.type === "integer") && finite) {
      const slider = document.createElement("input");
      slider.type = "range";
      slider.min = field.min;
      slider.max = field.max;
      slider.step = step(field);
      slider.dataset.path = field.path;
      const box = document.createElement("input");
      box.type = "number";
      box.step = "any";
      box.className = "number";
      const parse = (v) => (field.type === "integer" ? parseInt(v, 10) : parseFloat(v));
      slider.addEventListener("input", () => {
        box.value = slider.value;
        send(parse(slider.value), false);
      });
      slider.addEventListener("change", () => send(parse(slider.value), true));
      box.addEventListener("change", () => {
        slider.value = box.value;
        send(parse(box.value), true);
      });
      row.append(slider, box);
      set = (v) => {
        slider.value = v;
        box.value = v;
      };
    } else if (field.type === "number" || field.type === "integer" || field.type === "seed") {
      const box = document.createElement("input");
      box.type = "number";
      box.step = "any";
      box.className = "number wide";
      box.dataset.path = field.path;
      box.addEventListener("change", () => send(Number(box.value), true));
      row.append(box);
      set = (v) => (box.value = v);
    } else if (field.type === "boolean") {
      const box = document.createElement("input");
      box.type = "checkbox";
      box.dataset.path = field.path;
      box.addEventListener("change", () => send(box.checked, true));
      row.append(box);
      set = (v) => (box.checked = !!v);
    } else if (field.type === "choice") {
      const select = document.createElement("select");
      select.dataset.path = field.path;
      if (field.path === "color.preset") select.append(new Option("—", ""));
      for (const c of field.choices) select.append(new Option(c, c));
      select.addEventListener("change", () => select.value && send(select.value, true));
      row.append(select);
      set = (v) => (select.value = v ?? "");
    } else if (field.type === "map") {
      set = this.mapControl(field, row, send);
    } else {
      // Distributions, vectors, lists and paths: their TOML form as JSON text.
      const text = document.createElement("input");
      text.type = "text";
      text.className = "json";
      text.dataset.path = field.path;
      text.addEventListener("change", () => {
        let value = text.value;
        if (field.type !== "string" && field.type !== "path") {
          try {
            value = JSON.parse(text.value);
          } catch {
            message.textContent = "not JSON: write it as the TOML value in JSON, e.g. 25 or {\"procedural\": \"crown\"}";
            return;
          }
        }
        send(value, true);
      });
      row.append(text);
      set = (v) => (text.value = v === null ? "" : typeof v === "string" && (field.type === "string" || field.type === "path") ? v : JSON.stringify(v));
    }
    row.append(message);
    this.controls.set(field.path, {
      set,
      error: (text) => {
        message.textContent = text ?? "";
        row.classList.toggle("invalid", !!text);
      },
    });
    return row;
  }

  // A scalar map (§2.3): a constant with its slider, a procedural map by name, or an image
  // (painted or a file), the last two with the [low, high] their [0, 1] is scaled to.
  mapControl(field, row, send) {
    const box = document.createElement("div");
    box.className = "map-control";
    box.dataset.path = field.path;
    const kind = document.createElement("select");
    kind.append(new Option("constant", "constant"));
    for (const name of field.procedural ?? []) kind.append(new Option(name, name));
    const image = new Option("image", "image");
    kind.append(image);
    const slider = document.createElement("input");
    slider.type = "range";
    const top = Math.min(field.max, Math.max(4 * (field.map_high ?? 1), 1));
    slider.min = field.min;
    slider.max = top;
    slider.step = top / 500;
    const value = document.createElement("input");
    value.type = "number";
    value.step = "any";
    const low = document.createElement("input");
    const high = document.createElement("input");
    for (const [input, name] of [[low, "low"], [high, "high"]]) {
      input.type = "number";
      input.step = "any";
      input.title = `the map's ${name} end${field.unit ? ` (${field.unit})` : ""}`;
    }
    const file = document.createElement("span");
    file.className = "wide";
    let current = null;
    const show = (v) => {
      current = v;
      const constant = typeof v === "number";
      const isImage = !constant && v && "image" in v;
      image.hidden = !isImage;
      kind.value = constant ? "constant" : isImage ? "image" : v?.procedural ?? "constant";
      slider.hidden = value.hidden = !constant;
      low.hidden = high.hidden = constant;
      file.hidden = !isImage;
      if (constant) {
        slider.max = Math.max(top, v);
        slider.value = value.value = v;
      } else if (v) {
        low.value = v.low ?? field.map_low;
        high.value = v.high ?? field.map_high;
        file.textContent = isImage ? `${v.image} (Paint)` : "";
      }
    };
    kind.addEventListener("change", () => {
      if (kind.value === "constant") {
        const mid = typeof current === "number" ? current : Number(high.value || field.map_high);
        send(mid, true);
      } else if (kind.value !== "image") {
        send({ procedural: kind.value, low: Number(low.value || field.map_low), high: Number(high.value || field.map_high) }, true);
      }
    });
    slider.addEventListener("input", () => {
      value.value = slider.value;
      send(Number(slider.value), false);
    });
    slider.addEventListener("change", () => send(Number(slider.value), true));
    value.addEventListener("change", () => send(Number(value.value), true));
    const sendRange = () => {
      if (current && typeof current === "object")
        send({ ...current, low: Number(low.value), high: Number(high.value) }, true);
    };
    low.addEventListener("change", sendRange);
    high.addEventListener("change", sendRange);
    kind.className = "wide";
    box.append(kind, slider, value, low, high, file);
    row.append(box);
    return show;
  }

  setValues(values) {
    for (const [path, value] of Object.entries(values)) this.controls.get(path)?.set(value);
  }

  showError(path, text) {
    this.controls.get(path)?.error(text);
  }
}
