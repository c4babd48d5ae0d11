// xodrlint map: pan and zoom through the SVG viewBox, the findings list, search and hover.
// Plain JavaScript, no library: the page must work from disk with no network.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("map-data").textContent);
  var svg = document.getElementById("map");
  var UNITS_PER_METRE = Number(svg.getAttribute("data-units-per-metre"));
  var box = svg.viewBox.baseVal;
  var home = { x: box.x, y: box.y, w: box.width, h: box.height };
  var view = { x: home.x, y: home.y, w: home.w, h: home.h };
  var pending = false;

  // ---- view ---------------------------------------------------------------------------
  function unitsPerPixel() {
    var rect = svg.getBoundingClientRect();
    // preserveAspectRatio "meet": the axis that fills the element sets the scale
    return Math.max(view.w / Math.max(rect.width, 1), view.h / Math.max(rect.height, 1));
  }

  function render() {
    pending = false;
    svg.setAttribute("viewBox", view.x + " " + view.y + " " + view.w + " " + view.h);
    var upp = unitsPerPixel();
    svg.style.setProperty("--upp", String(upp));
    updateScaleBar(upp);
  }

  function schedule() {
    // one repaint per frame however many wheel or pointer events arrive
    if (!pending) {
      pending = true;
      window.requestAnimationFrame(render);
    }
  }

  function updateScaleBar(upp) {
    var metres = (120 * upp) / UNITS_PER_METRE;
    var power = Math.pow(10, Math.floor(Math.log10(metres)));
    var nice = [5, 2, 1].map(function (f) { return f * power; }).find(function (v) { return v <= metres; }) || power;
    document.getElementById("scale-bar").style.width = (nice * UNITS_PER_METRE) / upp + "px";
    document.getElementById("scale-label").textContent = nice >= 1000 ? nice / 1000 + " km" : nice + " m";
  }

  function toUnits(clientX, clientY) {
    var point = svg.createSVGPoint();
    point.x = clientX;
    point.y = clientY;
    var matrix = svg.getScreenCTM();
    return matrix ? point.matrixTransform(matrix.inverse()) : { x: view.x, y: view.y };
  }

  function zoomAt(factor, ux, uy) {
    var w = Math.min(Math.max(view.w * factor, 50), home.w * 20);
    factor = w / view.w;
    view.x = ux - (ux - view.x) * factor;
    view.y = uy - (uy - view.y) * factor;
    view.w = w;
    view.h *= factor;
    schedule();
  }

  function centreOn(ux, uy, width) {
    if (width !== undefined && width < view.w) {
      view.h *= width / view.w;
      view.w = width;
    }
    view.x = ux - view.w / 2;
    view.y = uy - view.h / 2;
    schedule();
  }

  function fitBox(minX, minY, maxX, maxY) {
    var margin = Math.max(maxX - minX, maxY - minY, 3000) * 0.3;
    var w = maxX - minX + 2 * margin;
    var h = maxY - minY + 2 * margin;
    var aspect = home.h / home.w;
    if (h > w * aspect) { w = h / aspect; } else { h = w * aspect; }
    view = { x: (minX + maxX - w) / 2, y: (minY + maxY - h) / 2, w: w, h: h };
    schedule();
  }

  var settling = 0;

  function moving() {
    // draw fast while the view moves, and crisp again once it rests
    svg.classList.add("dragging");
    window.clearTimeout(settling);
    settling = window.setTimeout(function () { svg.classList.remove("dragging"); }, 200);
  }

  svg.addEventListener("wheel", function (event) {
    event.preventDefault();
    moving();
    var at = toUnits(event.clientX, event.clientY);
    zoomAt(Math.exp(event.deltaY * 0.0015), at.x, at.y);
  }, { passive: false });

  var drag = null;
  svg.addEventListener("pointerdown", function (event) {
    drag = { x: event.clientX, y: event.clientY, moved: false, upp: unitsPerPixel() };
    svg.setPointerCapture(event.pointerId);
  });
  svg.addEventListener("pointermove", function (event) {
    if (!drag) { hover(event); return; }
    var dx = event.clientX - drag.x;
    var dy = event.clientY - drag.y;
    if (!drag.moved && Math.abs(dx) + Math.abs(dy) < 4) { return; }
    drag.moved = true;
    moving();
    view.x -= dx * drag.upp;
    view.y -= dy * drag.upp;
    drag.x = event.clientX;
    drag.y = event.clientY;
    schedule();
  });
  svg.addEventListener("pointerup", function (event) {
    var wasClick = drag && !drag.moved;
    drag = null;
    // the pointer is captured by the svg: find the marker under it ourselves
    var target = wasClick ? document.elementFromPoint(event.clientX, event.clientY) : null;
    if (target && target.classList.contains("finding")) {
      select(Number(target.getAttribute("data-finding")), false);
    }
  });
  document.getElementById("zoom-in").addEventListener("click", function () {
    zoomAt(0.5, view.x + view.w / 2, view.y + view.h / 2);
  });
  document.getElementById("zoom-out").addEventListener("click", function () {
    zoomAt(2, view.x + view.w / 2, view.y + view.h / 2);
  });
  document.getElementById("zoom-fit").addEventListener("click", function () {
    view = { x: home.x, y: home.y, w: home.w, h: home.h };
    schedule();
  });
  window.addEventListener("resize", schedule);

  // ---- findings -------------------------------------------------------------------------
  var rows = [];

  function cell(row, text, className) {
    var td = document.createElement("td");
    td.textContent = text;
    if (className) { td.className = className; }
    row.appendChild(td);
    return td;
  }

  function buildFindings() {
    var body = document.querySelector("#findings-table tbody");
    data.findings.forEach(function (finding, index) {
      var row = document.createElement("tr");
      row.setAttribute("data-finding", String(index));
      if (!finding.at) {
        row.className = "unplaced";
        row.title = "not on the map: no drawn element to place it at";
      }
      cell(row, finding.code);
      cell(row, finding.severity, "sev " + finding.severity);
      var message = cell(row, finding.message);
      var xpath = document.createElement("div");
      xpath.className = "xpath";
      xpath.textContent = finding.xpath;
      message.appendChild(xpath);
      cell(row, (finding.file ? finding.file + ":" : "") + finding.line);
      row.addEventListener("click", function () { select(index, true); });
      body.appendChild(row);
      rows.push(row);
    });
  }

  function select(index, centre) {
    document.querySelectorAll(".selected").forEach(function (el) { el.classList.remove("selected"); });
    var row = rows[index];
    if (!row) { return; }
    row.classList.add("selected");
    var marker = svg.querySelector('.finding[data-finding="' + index + '"]');
    if (marker) {
      marker.classList.add("selected");
      marker.parentNode.appendChild(marker); // on top of the others
      if (centre) {
        centreOn(Number(marker.getAttribute("cx")), Number(marker.getAttribute("cy")), 200 * UNITS_PER_METRE);
      }
    }
    if (!centre) { row.scrollIntoView({ block: "nearest" }); }
  }

  // ---- filters: by severity and by rule, each with its count -----------------------------
  // A city map under the official schemas carries thousands of schema findings around a
  // dozen railroad ones: unticking a rule hides its rows and its markers.
  var shown = { severity: {}, code: {} };
  var markers = [];

  function thousands(n) { return String(n).replace(/\B(?=(\d{3})+(?!\d))/g, ","); }

  function checkbox(group, kind, value, count) {
    var label = document.createElement("label");
    var box = document.createElement("input");
    box.type = "checkbox";
    box.checked = true;
    box.disabled = count === 0;
    box.setAttribute("data-" + kind, value);
    shown[kind][value] = true;
    box.addEventListener("change", function () {
      shown[kind][value] = box.checked;
      applyFilters();
    });
    label.appendChild(box);
    label.appendChild(document.createTextNode(" " + value + " (" + thousands(count) + ")"));
    if (count === 0) { label.className = "none"; }
    group.appendChild(label);
  }

  function tickEveryRule(ticked) {
    document.querySelectorAll("#rule-filter input").forEach(function (box) {
      box.checked = ticked;
      shown.code[box.getAttribute("data-code")] = ticked;
    });
    applyFilters();
  }

  function buildFilters() {
    var bySeverity = { error: 0, warning: 0, info: 0 };
    var byCode = {};
    data.findings.forEach(function (f) {
      bySeverity[f.severity] += 1;
      byCode[f.code] = (byCode[f.code] || 0) + 1;
    });
    var severities = document.getElementById("severity-filter");
    ["error", "warning", "info"].forEach(function (s) { checkbox(severities, "severity", s, bySeverity[s]); });
    var rules = document.getElementById("rule-filter");
    Object.keys(byCode).sort().forEach(function (code) { checkbox(rules, "code", code, byCode[code]); });
    svg.querySelectorAll("#findings .finding").forEach(function (marker) {
      markers[Number(marker.getAttribute("data-finding"))] = marker;
    });
    document.getElementById("rules-all").addEventListener("click", function () { tickEveryRule(true); });
    document.getElementById("rules-none").addEventListener("click", function () { tickEveryRule(false); });
    document.getElementById("filters").hidden = data.findings.length === 0;
    applyFilters();
  }

  function applyFilters() {
    var visible = 0;
    data.findings.forEach(function (f, index) {
      var on = shown.severity[f.severity] && shown.code[f.code];
      rows[index].hidden = !on;
      if (markers[index]) { markers[index].classList.toggle("filtered", !on); }
      if (on) { visible += 1; }
    });
    var total = data.findings.length;
    document.getElementById("filter-count").textContent = visible === total
      ? "showing all " + counted(total, "finding", "findings")
      : "showing " + thousands(visible) + " of " + counted(total, "finding", "findings");
  }

  // "1 switch", "2 switches": a count and its noun, singular for one
  function counted(n, one, many) { return thousands(n) + " " + (n === 1 ? one : many); }

  function buildSummary() {
    var counts = { error: 0, warning: 0, info: 0 };
    var unplaced = 0;
    data.findings.forEach(function (f) { counts[f.severity] += 1; if (!f.at) { unplaced += 1; } });
    document.getElementById("summary").textContent =
      counted(data.roadCount, "road", "roads") + ", " +
      counted(svg.querySelectorAll(".track").length, "track piece", "track pieces") + ", " +
      counted(svg.querySelectorAll(".switch").length, "switch", "switches") + ", " +
      counted(svg.querySelectorAll(".platform").length, "platform segment", "platform segments") + ". " +
      counted(data.findings.length, "finding", "findings") + " (" +
      counted(counts.error, "error", "errors") + ", " + counted(counts.warning, "warning", "warnings") +
      ", " + counts.info + " info)" + (unplaced ? ", " + unplaced + " not on the map." : ".");
    var list = document.getElementById("not-drawn");
    data.notDrawn.forEach(function (item) {
      var li = document.createElement("li");
      li.textContent = "line " + item.line + ": " + item.what + ": " + item.reason;
      list.appendChild(li);
    });
    document.getElementById("not-drawn-section").hidden = data.notDrawn.length === 0;
  }

  // ---- roads: read back from the shared path data --------------------------------------
  var roadIndex = null;

  function parseRoads() {
    if (roadIndex) { return roadIndex; }
    roadIndex = { list: [], byId: {} };
    var paths = svg.querySelectorAll("#roads path");
    data.roads.forEach(function (entries, k) {
      var chunks = (paths[k].getAttribute("d") || "").split("M").filter(Boolean);
      var next = 0;
      entries.forEach(function (entry) {
        var runs = chunks.slice(next, next + entry[2]).map(readRun);
        next += entry[2];
        var road = { id: entry[0], name: entry[1], runs: runs, d: chunks.slice(next - entry[2], next) };
        roadIndex.list.push(road);
        if (road.id !== null && !(road.id in roadIndex.byId)) { roadIndex.byId[road.id] = road; }
      });
    });
    roadIndex.grid = buildGrid(roadIndex.list);
    return roadIndex;
  }

  function readRun(chunk) {
    var numbers = chunk.match(/-?\d+/g).map(Number);
    var x = numbers[0];
    var y = numbers[1];
    var points = [x, y];
    for (var i = 2; i + 1 < numbers.length; i += 2) {
      x += numbers[i];
      y += numbers[i + 1];
      points.push(x, y);
    }
    return points;
  }

  var CELL = 50 * UNITS_PER_METRE;

  function buildGrid(roads) {
    var grid = new Map();
    roads.forEach(function (road, r) {
      road.runs.forEach(function (run) {
        for (var i = 0; i + 3 < run.length; i += 2) {
          var x0 = Math.floor(Math.min(run[i], run[i + 2]) / CELL);
          var x1 = Math.floor(Math.max(run[i], run[i + 2]) / CELL);
          var y0 = Math.floor(Math.min(run[i + 1], run[i + 3]) / CELL);
          var y1 = Math.floor(Math.max(run[i + 1], run[i + 3]) / CELL);
          for (var gx = x0; gx <= x1; gx++) {
            for (var gy = y0; gy <= y1; gy++) {
              var key = gx + "," + gy;
              if (!grid.has(key)) { grid.set(key, []); }
              grid.get(key).push(r, run, i);
            }
          }
        }
      });
    });
    return grid;
  }

  function distance(px, py, run, i) {
    var ax = run[i], ay = run[i + 1], dx = run[i + 2] - ax, dy = run[i + 3] - ay;
    var t = dx || dy ? ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy) : 0;
    t = Math.max(0, Math.min(1, t));
    return Math.hypot(px - ax - t * dx, py - ay - t * dy);
  }

  function nearestRoad(ux, uy, within) {
    var index = parseRoads();
    var best = null;
    var bestDistance = within;
    var entries = index.grid.get(Math.floor(ux / CELL) + "," + Math.floor(uy / CELL)) || [];
    for (var k = 0; k < entries.length; k += 3) {
      var d = distance(ux, uy, entries[k + 1], entries[k + 2]);
      if (d < bestDistance) { bestDistance = d; best = index.list[entries[k]]; }
    }
    return best;
  }

  // ---- hover labels ----------------------------------------------------------------------
  var label = document.getElementById("hover");

  function hover(event) {
    var text = null;
    var target = event.target;
    var titled = target.closest && target.closest("#map [data-finding], #map .switch, #map .platform, #map .track, #map .partner");
    if (titled && titled.querySelector("title")) {
      text = titled.querySelector("title").textContent;
    } else if (target === svg || (target.closest && target.closest("#roads"))) {
      var at = toUnits(event.clientX, event.clientY);
      var road = nearestRoad(at.x, at.y, 6 * unitsPerPixel());
      if (road) { text = "road '" + road.id + "'" + (road.name ? " (" + road.name + ")" : ""); }
    }
    label.hidden = !text;
    if (text) {
      var rect = svg.getBoundingClientRect();
      label.textContent = text;
      label.style.left = event.clientX - rect.left + 14 + "px";
      label.style.top = event.clientY - rect.top + 14 + "px";
    }
  }
  svg.addEventListener("pointerleave", function () { label.hidden = true; });

  // ---- search ----------------------------------------------------------------------------
  function attrEquals(name, value) {
    return "[" + name + '="' + value.replace(/["\\]/g, "\\$&") + '"]';
  }

  function boxOf(elements) {
    var b = null;
    elements.forEach(function (el) {
      var r = el.getBBox();
      b = b ? [Math.min(b[0], r.x), Math.min(b[1], r.y), Math.max(b[2], r.x + r.width), Math.max(b[3], r.y + r.height)]
            : [r.x, r.y, r.x + r.width, r.y + r.height];
    });
    return b;
  }

  function search(query) {
    document.querySelectorAll(".found").forEach(function (el) { el.classList.remove("found"); });
    var old = svg.querySelector(".found-road");
    if (old) { old.remove(); }
    var found = [];
    [["switch", ".switch" + attrEquals("data-id", query)],
     ["station", ".platform" + attrEquals("data-station", query)],
     ["platform", ".platform" + attrEquals("data-platform", query)],
     ["rail road", ".track" + attrEquals("data-road", query)]].forEach(function (pair) {
      var hits = Array.prototype.slice.call(svg.querySelectorAll(pair[1]));
      if (hits.length) { found.push([pair[0], hits]); }
    });
    var road = parseRoads().byId[query];
    if (road) {
      var path = document.createElementNS("http://www.w3.org/2000/svg", "path");
      path.setAttribute("class", "found-road found");
      path.setAttribute("d", road.d.map(function (c) { return "M" + c; }).join(""));
      svg.querySelector("#roads").appendChild(path);
      found.push(["road", [path]]);
    }
    var result = document.getElementById("search-result");
    if (!found.length) { result.textContent = "no road, switch or station '" + query + "'"; return; }
    var all = [];
    found.forEach(function (pair) { pair[1].forEach(function (el) { el.classList.add("found"); all.push(el); }); });
    result.textContent = "found: " + found.map(function (pair) { return pair[0] + " '" + query + "'"; }).join(", ");
    var b = boxOf(all);
    fitBox(b[0], b[1], b[2], b[3]);
  }

  document.getElementById("search").addEventListener("submit", function (event) {
    event.preventDefault();
    var query = document.getElementById("search-box").value.trim();
    if (query) { search(query); }
  });

  // ---- start -----------------------------------------------------------------------------
  buildFindings();
  buildFilters();
  buildSummary();
  render();
  var wanted = /^#finding=(\d+)$/.exec(window.location.hash);
  if (wanted) { select(Number(wanted[1]), true); }
  document.body.setAttribute("data-ready", "true");
})();
