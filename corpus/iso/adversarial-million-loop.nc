%
O7105 (ADVERSARIAL: A LOOP OF A MILLION ITERATIONS)
(The analysis follows the loop up to its bound and says so; it never runs a million times.)
G21 G90 G54
#1=0
WHILE [#1 LT 1000000] DO1
#1=#1+1
END1
M30
%
