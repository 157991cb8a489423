// Validates Lottie JSON files against the Lottie JSON schema of lottie-specs. Prints one line
// per file (errors and warnings counted, and the first errors), and exits with 1 if any file
// has an error. Warnings name properties the specification does not define (players' own
// extensions such as a layer's start time), which players accept.
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";

const require = createRequire(import.meta.url);
const { LottieValidator, get_schema_path } = require("@lottie-animation-community/lottie-specs/src/validator-node.js");
const Ajv2020 = require("ajv/dist/2020").default;

const schema = JSON.parse(readFileSync(get_schema_path(), "utf8"));
const validator = new LottieValidator(Ajv2020, schema);
let failed = false;
for (const file of process.argv.slice(2)) {
  const issues = validator.validate(JSON.parse(readFileSync(file, "utf8")));
  const errors = issues.filter((i) => i.type === "error");
  const warnings = issues.length - errors.length;
  console.log(`${file}: ${errors.length} errors, ${warnings} warnings`);
  for (const e of errors.slice(0, 5)) console.log(`  ${e.path}: ${e.message}`);
  failed ||= errors.length > 0;
}
process.exit(failed ? 1 : 0);
