// expect: 3: 'within Other' but the file lies in ValidLib
// expect: 5: class WrongWithin closed by 'end WrongWithn'
within Other;
model WrongWithin "A file that claims another package, a class closed by another name"
end WrongWithn;
