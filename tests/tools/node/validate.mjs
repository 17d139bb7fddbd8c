// tests/tools/node/validate.mjs FILE.glb NODE_MODULES: the Khronos glTF validator's report on
// FILE (its JS API, validateBytes). Prints every issue; exits 1 on any error or warning.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const [file, modules] = process.argv.slice(2);
const require = createRequire(path.join(path.resolve(modules), 'x.js'));
const validator = require('gltf-validator');
const bytes = new Uint8Array(fs.readFileSync(file));
const report = await validator.validateBytes(bytes, { maxIssues: 1000, uri: path.basename(file) });
const issues = report.issues;
console.log(`gltf-validator ${report.validatorVersion}: ${file}: ${issues.numErrors} error(s), ` +
            `${issues.numWarnings} warning(s), ${issues.numInfos} info(s), ${issues.numHints} hint(s)`);
const severity = ['error', 'warning', 'info', 'hint'];
for (const m of issues.messages)
  console.log(`  ${severity[m.severity]}: ${m.code} at ${m.pointer ?? ''}: ${m.message}`);
const info = report.info ?? {};
console.log(`  info: ${JSON.stringify({ animationCount: info.animationCount, morphTargets: info.maxAttributes, totalVertexCount: info.totalVertexCount })}`);
process.exit(issues.numErrors === 0 && issues.numWarnings === 0 ? 0 : 1);
