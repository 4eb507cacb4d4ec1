// Foxglove's own OMG IDL parser and CDR decoder (what Foxglove's and Lichtblick's players decode a `cdr`+`omgidl`
// channel with), from e2e/node_modules (`npm ci` in e2e/): an independent decoder of the Foxglove gateway's raw
// channels. Reads a JSON array of {schemaName, schema, messages: [base64 CDR]} on stdin and writes, for each, the
// decoded messages as plain JSON (typed arrays as arrays, 64-bit integers as numbers) or the error each raised.
// Usage: node omgidl_decode.cjs < channels.json
"use strict";
const path = require("node:path");
const { createRequire } = require("node:module");

const e2e = createRequire(path.resolve(__dirname, "../../../e2e/package.json"));
let parseIDL, MessageReader, versions;
try {
  ({ parseIDL } = e2e("@foxglove/omgidl-parser"));
  ({ MessageReader } = e2e("@foxglove/omgidl-serialization"));
  versions = {
    parser: e2e("@foxglove/omgidl-parser/package.json").version,
    serialization: e2e("@foxglove/omgidl-serialization/package.json").version,
  };
} catch (e) {
  process.stderr.write(`Foxglove's OMG IDL decoder is not installed: run \`npm ci\` in e2e/ (${e.message})\n`);
  process.exit(2);
}

function plain(v) {
  if (typeof v === "bigint") return Number(v);
  if (ArrayBuffer.isView(v)) return Array.from(v, plain);
  if (Array.isArray(v)) return v.map(plain);
  if (v !== null && typeof v === "object") {
    const out = {};
    for (const [k, x] of Object.entries(v)) if (x !== undefined) out[k] = plain(x);
    return out;
  }
  return v;
}

const input = JSON.parse(require("node:fs").readFileSync(0, "utf8"));
const out = input.map(({ schemaName, schema, messages }) => {
  let reader;
  try {
    reader = new MessageReader(schemaName, parseIDL(schema));
  } catch (e) {
    return { error: `schema: ${e.message}`, decoded: [] };
  }
  return {
    decoded: messages.map((m) => {
      try {
        return { value: plain(reader.readMessage(Buffer.from(m, "base64"))) };
      } catch (e) {
        return { error: e.message };
      }
    }),
  };
});
process.stdout.write(JSON.stringify({ versions, channels: out }));
