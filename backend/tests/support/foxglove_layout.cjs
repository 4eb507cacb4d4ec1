// Checks a Foxglove layout file against the published TypeScript type of Foxglove's layout format: `Layout` of
// @foxglove/embed (from e2e/node_modules, `npm ci` in e2e/), turned into a JSON Schema here with
// ts-json-schema-generator and applied with Ajv. Each node of the layout is checked against the type its `type` names
// (a panel against its panel type's own definition, found by its `panelType`, and its `config` against that type's
// config), strictly: a key the type does not have, or a value not of its type, is an error. Writes {"versions",
// "errors": [{path, type, key, message}]}, `type` the definition at fault and `key` the key.
// Usage: node foxglove_layout.cjs LAYOUT.json
"use strict";
const fs = require("node:fs");
const os = require("node:os");
const path = require("node:path");
const { createRequire } = require("node:module");

const e2e = createRequire(path.resolve(__dirname, "../../../e2e/package.json"));
let createGenerator, Ajv, embedTypes, versions;
try {
  ({ createGenerator } = e2e("ts-json-schema-generator"));
  Ajv = e2e("ajv").default;
  embedTypes = e2e.resolve("@foxglove/embed/dist/cjs/types.d.ts");
  versions = {
    "@foxglove/embed": e2e("@foxglove/embed/package.json").version,
    "ts-json-schema-generator": e2e("ts-json-schema-generator/package.json").version,
    ajv: e2e("ajv/package.json").version,
  };
} catch (e) {
  process.stderr.write(`Foxglove's layout type or its checker is not installed: run \`npm ci\` in e2e/ (${e.message})\n`);
  process.exit(2);
}

function schemaOf(file, type) {
  const config = { path: file, type, expose: "export", skipTypeCheck: true, additionalProperties: false };
  return createGenerator(config).createSchema(type);
}

const layout = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const defs = schemaOf(embedTypes, "*").definitions;
// the type of each panel named by its panelType (e.g. "Map" -> MapPanel); generic panels are BasePanel
const panelTypes = {};
for (const [name, def] of Object.entries(defs)) {
  const panelType = def.properties && def.properties.panelType && def.properties.panelType.const;
  if (typeof panelType === "string") panelTypes[panelType] = name;
}
// a panel type's config, as the type itself says (`Exclude<MapPanel["config"], undefined>`): an intersection with
// BasePanel's `config: unknown` reads as anything in the generated schema above
const children = (n) => [
  ...(n.items || []).map((i) => i.content),
  ...(n.tabs || []).map((t) => t.content),
  ...(n.panels || []).map((i) => i.panel),
];
const panelsOf = (n) => (!n || typeof n !== "object" ? [] : n.type === "panel" ? [n] : children(n).flatMap(panelsOf));
const used = [...new Set(panelsOf(layout.content).map((p) => panelTypes[p.panelType]))].filter(Boolean);
const configs = {};
if (used.length > 0) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "layout-"));
  const from = JSON.stringify(embedTypes.replace(/\.d\.ts$/, ""));
  const lines = used.map((t) => `export type ${t}Config_ = Exclude<import(${from}).${t}["config"], undefined>;`);
  fs.writeFileSync(path.join(dir, "configs.ts"), lines.join("\n") + "\n");
  try {
    Object.assign(defs, schemaOf(path.join(dir, "configs.ts"), "*").definitions);
  } finally {
    fs.rmSync(dir, { recursive: true, force: true });
  }
  for (const t of used) configs[t] = `${t}Config_`;
}
// a node's own keys only: what it contains is checked as a node of its own
defs.Content = {};
// a panel's settings that a layout leaves out are the panel's defaults (foxglove-sdk's layout classes write only those
// set), so a config is held to the keys and values it has, not to every setting the type requires; an object type
// without an index signature has no other keys (the generator leaves that unsaid for a type reached through an alias)
const settings = (v) => {
  if (Array.isArray(v)) return v.map(settings);
  if (!v || typeof v !== "object") return v;
  const out = Object.fromEntries(
    Object.entries(v)
      .filter(([k]) => k !== "required")
      .map(([k, x]) => [k, settings(x)]),
  );
  if (out.properties && !("additionalProperties" in out)) out.additionalProperties = false;
  return out;
};
const ajv = new Ajv({ allErrors: true, strict: false });
ajv.addSchema({ definitions: defs }, "layout");
ajv.addSchema({ definitions: settings(defs) }, "settings");
const check = (schema, def, value) => {
  const validate = ajv.getSchema(`${schema}#/definitions/${def}`);
  return validate(value) ? [] : validate.errors;
};

const errors = [];
function say(at, def, errs) {
  for (const e of errs) {
    // the definition at fault: the one checked, or one it refers to (`#/definitions/SplitItem/required`)
    const [, where, name] = e.schemaPath.split("/");
    const key = e.params.missingProperty || e.params.additionalProperty || e.instancePath.split("/").pop();
    const allowed = e.params.allowedValues ? ` (${e.params.allowedValues.join(", ")})` : "";
    const type = where === "definitions" ? name : def;
    errors.push({ path: `${at}${e.instancePath}`, type, key, message: `${e.message}${allowed}` });
  }
}
function node(at, value) {
  const kinds = { split: "Split", tabs: "Tabs", stack: "Stack" };
  if (value && value.type === "panel") {
    const def = panelTypes[value.panelType] || "BasePanel";
    say(at, def, check("layout", def, value));
    if (configs[def] && value.config !== undefined) {
      say(`${at}/config`, `${def}.config`, check("settings", configs[def], value.config));
    }
  } else if (value && kinds[value.type]) {
    say(at, kinds[value.type], check("layout", kinds[value.type], value));
    const where = { split: ["items", "content"], tabs: ["tabs", "content"], stack: ["panels", "panel"] }[value.type];
    (value[where[0]] || []).forEach((item, i) => node(`${at}/${where[0]}/${i}/${where[1]}`, item[where[1]]));
  } else {
    errors.push({ path: at, type: "Content", key: "type", message: "is not a panel, split, tabs or stack" });
  }
}
say("", "Layout", check("layout", "Layout", layout));
node("/content", layout.content);
process.stdout.write(JSON.stringify({ versions, errors }) + "\n");
