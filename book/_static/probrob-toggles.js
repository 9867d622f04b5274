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
  // axe "label-content-name-mismatch": the colour-mode button is named "Color mode" but its
  // icons' titles ("Light", "Dark", "System Settings") read as its text: the icons are decoration.
  // Font Awesome's deferred script replaces each <i> by an <svg> whose <title> carries the
  // title, either before or after this script runs (a race): both forms are quietened, now and
  // whenever the button's icons are replaced later.
  function quietIcon(icon) {
    icon.setAttribute("aria-hidden", "true");
    icon.removeAttribute("title");
    icon.removeAttribute("aria-labelledby");
    icon.removeAttribute("role");
    icon.querySelectorAll("title").forEach(function (t) {
      t.remove();
    });
  }
  function quietThemeIcons() {
    document.querySelectorAll(".theme-switch-button").forEach(function (button) {
      const quiet = function () {
        button.querySelectorAll(".theme-switch").forEach(quietIcon);
      };
      quiet();
      new MutationObserver(quiet).observe(button, {childList: true, subtree: true});
    });
  }
  // axe "label-content-name-mismatch": myst-nb's hidden-cell <summary> is named "Toggle hidden
  // content" but reads "Show code cell content": its visible text is its name.
  function nameSummaries() {
    document.querySelectorAll("summary[aria-label='Toggle hidden content']").forEach(function (s) {
      if (s.textContent.trim()) s.removeAttribute("aria-label");
    });
  }
  // axe "aria-allowed-role", "aria-deprecated-role", "aria-required-children": docutils marks
  // each bibliography entry role="doc-biblioentry" (deprecated) inside role="list": they are
  // the list's items.
  function listCitations() {
    document.querySelectorAll("[role='list'] > [role='doc-biblioentry']").forEach(function (c) {
      c.setAttribute("role", "listitem");
    });
  }
  // axe "region": the primary sidebar is a plain <div>; its first item (the book's title and
  // logo link) is outside every landmark. The sidebar is a complementary region of the page.
  function landmarkSidebar() {
    const sidebar = document.getElementById("pst-primary-sidebar");
    if (sidebar && !sidebar.hasAttribute("role")) {
      sidebar.setAttribute("role", "complementary");
      sidebar.setAttribute("aria-label", "Book navigation");
    }
  }
  function init() {
    quietThemeIcons();
    landmarkSidebar();
    nameSummaries();
    listCitations();
    wire("primary");
    wire("secondary");
    nameSearchFields();
  }
  if (document.readyState !== "loading") init();
  else document.addEventListener("DOMContentLoaded", init);
})();
