// SPDX-License-Identifier: Apache-2.0
#include "stream_page.h"

namespace navmap::ipc::stream_detail {

namespace {

// Profile names reach the page as JavaScript string literals and button labels: only the
// characters a profile name needs survive.
std::string safeName(const std::string& name) {
    std::string safe;
    for (const char c : name) {
        if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_') {
            safe += c;
        }
    }
    return safe;
}

}  // namespace

std::string viewerPage(const std::string& profile, const std::vector<std::string>& profiles) {
    const std::string safe = safeName(profile);
    std::string buttons;
    for (const auto& p : profiles.empty() ? std::vector<std::string>{"cluster", "hud", "center"} : profiles) {
        const std::string name = safeName(p);
        buttons += "<button onclick=\"show('" + name + "')\">" + name + "</button>";
    }
    return R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>navmap live view</title>
<style>
body{margin:0;background:#1b1d21;color:#d8dde3;font:14px system-ui,sans-serif}
header{padding:8px 12px;background:#25282e;display:flex;gap:12px;align-items:center}
header b{font-size:16px} button{background:#3a3f47;color:#d8dde3;border:0;padding:4px 10px;border-radius:3px}
main{display:flex;flex-wrap:wrap;gap:12px;padding:12px}
img{max-width:100%;background:#000;border:1px solid #3a3f47}
pre{margin:0;padding:8px;background:#25282e;min-width:320px;white-space:pre-wrap}
#state{padding:2px 8px;border-radius:3px;background:#555}
figure{margin:0} figcaption{font-size:12px;color:#aab2bc;padding-top:4px}
figcaption a{color:#aab2bc}
</style></head><body>
<header><b>navmap</b>)HTML" +
           buttons + R"HTML(<span id="state">connecting</span></header>
<main><figure><img id="view" alt="live map stream">
<figcaption id="attribution">Map data &copy; <a href="https://www.openstreetmap.org/copyright">OpenStreetMap contributors</a> (ODbL); elevation SRTM: NASA/USGS</figcaption></figure>
<pre id="status">waiting for /status</pre></main>
<script>
// A page opened as /?token=... hands the token on to the stream and /status.
const token=new URLSearchParams(location.search).get('token');
function withToken(u){return token?u+(u.includes('?')?'&':'?')+'token='+encodeURIComponent(token):u;}
function show(p){document.getElementById('view').src=withToken('/stream.mjpg?profile='+p);}
document.getElementById('view').src=withToken('/stream.mjpg?profile=)HTML" +
           safe + R"HTML(');
async function poll(){
  const st=document.getElementById('state');
  try{const r=await fetch(withToken('/status'),{cache:'no-store'});if(!r.ok)throw new Error('HTTP '+r.status);const j=await r.json();
    document.getElementById('status').textContent=JSON.stringify(j,null,2);
    st.textContent='live: '+j.stream.clients+' client(s), '+j.stream.published+' frames';st.style.background='#2e7d32';
  }catch(e){st.textContent='no status: '+e;st.style.background='#b71c1c';}
}
poll();setInterval(poll,1000);
</script></body></html>
)HTML";
}

}  // namespace navmap::ipc::stream_detail
