// expect: 7: resetHandle: vl_reset is declared in none of validlib.h
// expect: 12: closeHandle: vl_close is only declared in validlib.h (its code is in a library): the external clause needs a Library annotation
within ValidLib;
package ExternalMissing "A C function the header does not declare; a library function without Library"
  function resetHandle
    input Handle handle;
    external "C" vl_reset(handle) annotation (Library = "validlib", Include = "#include \"validlib.h\"");
  end resetHandle;

  function closeHandle
    input Handle handle;
    external "C" vl_close(handle) annotation (Include = "#include \"validlib.h\"");
  end closeHandle;
end ExternalMissing;
