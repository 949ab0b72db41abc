// expect: 14: ExternalArgType -> vl_exchange: argument 4 'enabled' maps to double, parameter 4 (enabled) of the prototype is int
// expect: 14: ExternalArgType -> vl_exchange: argument 7 'received' has 4 elements, parameter received is declared [3]
// expect: 14: ExternalArgType -> vl_exchange: argument 2 'values' maps to double*
within ValidLib;
impure function ExternalArgType "A Real for an int, an array one too long, an output for an input array"
  input Handle handle;
  output Real values[3];
  input Real enabled;
  input Units unitChoice;
  output Integer status;
  output Integer counts[2];
  output Real received[4];
  output String message;
  external "C" status = vl_exchange(handle, values, size(values, 1), enabled, unitChoice, counts, received, message)
    annotation (Library = "validlib", Include = "#include \"validlib.h\"");
end ExternalArgType;
