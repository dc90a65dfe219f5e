// Validates an OpenAPI document (megavox serve's /v1/openapi.json) with @apidevtools/swagger-parser: the
// schema of OpenAPI 3 and every $ref resolved. Usage: node check_openapi.mjs FILE
import SwaggerParser from "@apidevtools/swagger-parser";

const file = process.argv[2];
try {
  const api = await SwaggerParser.validate(file);
  console.log(`${file}: valid OpenAPI ${api.openapi}, ${Object.keys(api.paths).length} paths`);
} catch (e) {
  console.error(`${file}: ${e.message}`);
  process.exit(1);
}
