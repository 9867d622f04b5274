// probrob: make the article header's sidebar buttons work (sphinx-book-theme 1.3 /
// pydata-sphinx-theme 0.17). Both themes bind their sidebar handlers with
// document.querySelector(".primary-toggle") / (".secondary-toggle"), i.e. to the FIRST such
// button: the one in pydata's header navbar, which sphinx-book-theme hides. The visible buttons
// (in .bd-header-article) therefore had no handler: at 390 px neither opened its sidebar, at
// 1280 px the menu button could not collapse the primary sidebar. Here a click on any other
// toggle is forwarded to the first one, which carries both themes' handlers (the book theme's
// wide-screen collapse, pydata's narrow-screen dialog).
(function () {
  "use strict";
  function wire(kind) {
    const buttons = document.querySelectorAll("." + kind + "-toggle");
    if (buttons.length < 2) return;
    const bound = buttons[0];
    buttons.forEach(function (button) {
      if (button === bound) return;
      button.addEventListener("click", function (event) {
        event.preventDefault();
        event.stopPropagation();
        bound.click();
        button.blur();
      });
    });
  }
  // axe "label-content-name-mismatch": pydata's search fields say "Search Ctrl + K" but are
  // named "Search"; without the aria-label their name is their visible text.
  function nameSearchFields() {
    document.querySelectorAll("button.search-button-field[aria-label]").forEach(function (b) {
      if (b.textContent.trim()) b.removeAttribute("aria-label");
    });
  }
  function init() {
    wire("primary");
    wire("secondary");
    nameSearchFields();
  }
  if (document.readyState !== "loading") init();
  else document.addEventListener("DOMContentLoaded", init);
})();
