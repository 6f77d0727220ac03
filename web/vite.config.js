// The editor's bundle: index.html and src/ into one JS and one CSS file, served by
// `wisp edit` (src/edit/CMakeLists.txt runs this build and embeds dist/ into the binary).
import { defineConfig } from "vite";

export default defineConfig({
  base: "/",
  build: {
    target: "es2022",
    chunkSizeWarningLimit: 1024,
    assetsInlineLimit: 0,
  },
});
