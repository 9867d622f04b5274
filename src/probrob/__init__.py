"""probrob: the library behind the *probrob* book.

Tested implementations of *Probabilistic Robotics* (Thrun, Burgard & Fox, 2005),
chapters 5-7. Function names are the book's algorithm names; each docstring cites
the table it implements and the deck formula it corrects, if any.
"""

__version__ = "0.1.0"
