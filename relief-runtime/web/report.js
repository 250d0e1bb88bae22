// relief report: sortable and filterable tables, and in-page links that open folded sections.
// No library; the page reads fine without this script (tables unsorted, sections folded).
"use strict";

(function () {
  // A cell's sort key: a number when the cell reads as one ("1.23e-4", "0.512", "12.5%",
  // "1.6×", "#3"), else its text. Empty, "—", "NaN" and "error" sort last either way.
  function key(cell) {
    var t = (cell ? cell.textContent : "").trim();
    if (t === "" || t === "—" || t === "NaN" || t === "error") return { missing: true };
    var m = t.match(/^[#≥<]?\s*(-?\d+(?:\.\d+)?(?:e[-+]?\d+)?)/i);
    if (m) return { num: parseFloat(m[1]), text: t };
    return { text: t.toLowerCase() };
  }

  function compare(a, b) {
    if (a.missing || b.missing) return (a.missing ? 1 : 0) - (b.missing ? 1 : 0);
    if (a.num !== undefined && b.num !== undefined) return a.num - b.num;
    if (a.num !== undefined) return -1;
    if (b.num !== undefined) return 1;
    return a.text < b.text ? -1 : a.text > b.text ? 1 : 0;
  }

  function sortBy(table, col, th) {
    var body = table.tBodies[0];
    if (!body) return;
    var dir = th.getAttribute("aria-sort") === "ascending" ? "descending" : "ascending";
    var ths = table.tHead ? table.tHead.rows[0].cells : [];
    for (var i = 0; i < ths.length; i++) ths[i].removeAttribute("aria-sort");
    th.setAttribute("aria-sort", dir);
    var rows = Array.prototype.slice.call(body.rows);
    var keyed = rows.map(function (r, i) { return { r: r, k: key(r.cells[col]), i: i }; });
    keyed.sort(function (a, b) {
      var c = compare(a.k, b.k);
      if (a.k.missing || b.k.missing) return c || a.i - b.i; // missing last in both directions
      if (dir === "descending") c = -c;
      return c || a.i - b.i;
    });
    keyed.forEach(function (x) { body.appendChild(x.r); });
  }

  function makeSortable(table) {
    if (!table.tHead || !table.tHead.rows.length) return;
    var ths = table.tHead.rows[0].cells;
    for (var i = 0; i < ths.length; i++) {
      (function (col, th) {
        th.tabIndex = 0;
        th.title = "sort by this column";
        th.addEventListener("click", function () { sortBy(table, col, th); });
        th.addEventListener("keydown", function (e) {
          if (e.key === "Enter" || e.key === " ") { e.preventDefault(); sortBy(table, col, th); }
        });
      })(i, ths[i]);
    }
  }

  // The column a filter reads: the one headed "pipeline" (or naming a pipeline), else all.
  function pipelineColumn(table) {
    if (!table.tHead || !table.tHead.rows.length) return -1;
    var ths = table.tHead.rows[0].cells;
    for (var i = 0; i < ths.length; i++) {
      if (/pipeline|method/i.test(ths[i].textContent)) return i;
    }
    return -1;
  }

  function wireFilter(input) {
    var table = document.getElementById(input.getAttribute("data-table"));
    if (!table || !table.tBodies[0]) return;
    var col = pipelineColumn(table);
    input.addEventListener("input", function () {
      var q = input.value.trim().toLowerCase();
      var rows = table.tBodies[0].rows;
      for (var i = 0; i < rows.length; i++) {
        var cell = col >= 0 ? rows[i].cells[col] : rows[i];
        var text = cell ? cell.textContent.toLowerCase() : "";
        rows[i].hidden = q !== "" && text.indexOf(q) < 0;
      }
    });
  }

  // An in-page link to something inside folded sections opens them, then scrolls to it.
  function reveal(id) {
    if (!id) return;
    var el = document.getElementById(decodeURIComponent(id));
    if (!el) return;
    for (var p = el; p; p = p.parentElement) {
      if (p.tagName === "DETAILS") p.open = true;
    }
    el.scrollIntoView();
  }

  function init() {
    var tables = document.querySelectorAll("table.sortable");
    for (var i = 0; i < tables.length; i++) makeSortable(tables[i]);
    var filters = document.querySelectorAll("input.filter[data-table]");
    for (var j = 0; j < filters.length; j++) {
      filters[j].hidden = false;
      wireFilter(filters[j]);
    }
    window.addEventListener("hashchange", function () { reveal(location.hash.slice(1)); });
    if (location.hash) reveal(location.hash.slice(1));
  }

  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", init);
  else init();
})();
