!> The XDMF index of the particle outputs (write_xdmf of mpm_output): the XDMF 3 time
!> series that ParaView opens, listing every output file (or part) written so far, with the
!> attributes of the output field table; and the names of those files.
submodule(mpm_output) mpm_output_xdmf
    implicit none

contains

    !> Whether output field i is written as a dataset and an attribute (see the interface).
    module pure function attribute(writer, i) result(listed)
        type(output_writer_type), intent(in) :: writer
            !! the run's writer
        integer, intent(in) :: i
            !! index in output_fields
        logical :: listed
            !! written as a dataset and an attribute

        listed = writer%fields(i) .and. .not. output_fields(i)%geometry
    end function attribute

    !> Rewrite <dir>/<case>.xdmf listing every file written so far (via a .tmp and rename).
    !>
    !> With several images each time is a spatial collection of the parts; a part without
    !> particles is left out (a Polyvertex of 0 elements upsets some readers), its grid is
    !> not, and when no part has particles the first one is listed so every time has one.
    module subroutine write_xdmf(writer, error)
        type(output_writer_type), intent(in) :: writer
            !! writer of image 1, with the records of every output time
        type(error_type), allocatable, intent(out) :: error
            !! set when the index cannot be written

        character(len=:), allocatable :: path
        type(text_file_type) :: file
        integer :: i, part
        character(len=:), allocatable :: indent
        type(error_type), allocatable :: ignored

        path = writer%dir//"/"//writer%case_name//".xdmf"
        ! (a Fortran write would not see a full disk: gfortran drops those errors)
        call open_text_file(path//".tmp", file, error, shown_as=path)
        if (allocated(error)) return
        indent = ""
        call put('<?xml version="1.0" ?>')
        call put('<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>')
        call put('<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">')
        call put("  <Domain>")
        indent = ""
        if (writer%grid .or. writer%images > 1) then
            ! one spatial collection per time, of the particles and the grid (with the
            ! Xdmf3ReaderT reader ParaView names the two blocks "particles" and "grid") of
            ! each part: ParaView shows the parts of a time together
            if (writer%grid) then
                call put('    <Grid Name="particles_and_grid" GridType="Collection" '// &
                    'CollectionType="Temporal">')
            else
                call put('    <Grid Name="particles" GridType="Collection" '// &
                    'CollectionType="Temporal">')
            end if
            do i = 1, writer%count
                call put('      <Grid Name="output_'//int_text(i - 1)// &
                    '" GridType="Collection" CollectionType="Spatial">')
                call put('        <Time Value="'//real_text(writer%records(i)%time)//'"/>')
                indent = "  "
                do part = 1, writer%images
                    if (listed(writer%records(i)%counts, part)) then
                        call put_particles(writer%records(i), i - 1, part)
                    end if
                    if (writer%grid) call put_grid(writer%records(i), i - 1, part)
                end do
                indent = ""
                call put("      </Grid>")
            end do
        else
            call put('    <Grid Name="particles" GridType="Collection" CollectionType="Temporal">')
            do i = 1, writer%count
                call put_particles(writer%records(i), i - 1, 1)
            end do
        end if
        call put("    </Grid>")
        call put("  </Domain>")
        call put("</Xdmf>")
        call close_text_file(file, error)
        if (allocated(error)) then
            ! the index of the outputs before stays as it was
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)

    contains

        subroutine put(line)
            character(len=*), intent(in) :: line
                !! line without its indentation

            call put_line(file, indent//line)
        end subroutine put

        subroutine put_particles(record, index, part)
            type(output_record_type), intent(in) :: record
                !! output time
            integer, intent(in) :: index
                !! output index (0-based)
            integer, intent(in) :: part
                !! image whose file is listed

            character(len=:), allocatable :: n, file, source, name, number_type
            type(particle_field_type) :: described
            integer :: c, nstress, i

            n = int_text(record%counts(part))
            file = part_file_name(index, part, writer%images)
            source = file//":/particles/"
            ! Voigt order: the first 4 components in 2D, all 6 in 3D
            nstress = merge(4, 6, writer%dim == 2)
            call put('      <Grid Name="particles" GridType="Uniform">')
            call put('        <Time Value="'//real_text(record%time)//'"/>')
            ! the connectivity is explicit: Xdmf3ReaderS makes no cell without it
            call put('        <Topology TopologyType="Polyvertex" NumberOfElements="'//n// &
                '" NodesPerElement="1">')
            call put("          "//data_item(n, "Int", file//":/xdmf/vertices"))
            call put("        </Topology>")
            call put('        <Geometry GeometryType="XYZ">')
            call put("          "//data_item(n//" 3", "Float", source//"position"))
            call put("        </Geometry>")
            do i = 1, nfields
                if (.not. attribute(writer, i)) cycle
                name = trim(output_fields(i)%name)
                number_type = "Float"
                described = particle_field(field_index(trim(output_fields(i)%source)))
                if (described%whole) number_type = "Int"
                select case (output_fields(i)%layout)
                case (layout_vector)
                    call put_attribute(name, "Vector", n//" 3", number_type, source//name)
                case (layout_voigt)
                    call put_attribute(name, "Matrix", n//" "//int_text(nstress), number_type, &
                        source//name)
                    do c = 1, nstress
                        call put_component(name, c, n, file)
                    end do
                case default
                    call put_attribute(name, "Scalar", n, number_type, source//name)
                end select
            end do
            if (record%id) call put_attribute("id", "Scalar", n, "Int", source//"id")
            call put("      </Grid>")
        end subroutine put_particles

        !> The grid as a regular (co-rectilinear) mesh, so ParaView shows it as a surface.
        subroutine put_grid(record, index, part)
            type(output_record_type), intent(in) :: record
                !! output time
            integer, intent(in) :: index
                !! output index (0-based)
            integer, intent(in) :: part
                !! image whose grid is listed

            character(len=:), allocatable :: mesh, source
            integer :: nn(3)
            real(wp) :: origin(3)

            nn = writer%grid_nn(:, part)
            origin = writer%grid_origin(:, part)
            source = part_file_name(index, part, writer%images)//":/grid/"
            call put('      <Grid Name="grid" GridType="Uniform">')
            call put('        <Time Value="'//real_text(record%time)//'"/>')
            ! XDMF lists the slowest direction first: z y x
            mesh = int_text(nn(3))//" "//int_text(nn(2))//" "//int_text(nn(1))
            call put('        <Topology TopologyType="3DCoRectMesh" Dimensions="'//mesh//'"/>')
            call put('        <Geometry GeometryType="ORIGIN_DXDYDZ">')
            call put('          <DataItem Dimensions="3" NumberType="Float" Precision="8" '// &
                'Format="XML">'//real_text(origin(3))//" "//real_text(origin(2))//" "// &
                real_text(origin(1))//"</DataItem>")
            call put('          <DataItem Dimensions="3" NumberType="Float" Precision="8" '// &
                'Format="XML">'//real_text(writer%grid_dx)//" "//real_text(writer%grid_dx)// &
                " "//real_text(writer%grid_dx)//"</DataItem>")
            call put("        </Geometry>")
            ! the node arrays are given the shape of the mesh (the same values in the same
            ! order): XDMFReader fails on a vector of shape (nnodes, 3) on a structured mesh
            call put_attribute("mass", "Scalar", mesh, "Float", source//"mass")
            call put_attribute("velocity", "Vector", mesh//" 3", "Float", source//"velocity")
            call put_attribute("reaction", "Vector", mesh//" 3", "Float", source//"reaction")
            call put("      </Grid>")
        end subroutine put_grid

        subroutine put_attribute(name, kind, dims, number_type, source)
            character(len=*), intent(in) :: name, kind, dims, number_type, source

            call put('        <Attribute Name="'//name//'" AttributeType="'//kind// &
                '" Center="Node">')
            call put("          "//data_item(dims, number_type, source))
            call put("        </Attribute>")
        end subroutine put_attribute

        !> Column c of /particles/<name> as a scalar attribute "<name>_<component>", read
        !> from its view /xdmf/<name>_<component> (write_xdmf_group).
        !>
        !> The readers share no way of selecting a column: XDMFReader fails on the XDMF 3
        !> hyperslab path "file:/dataset|start:stride:count:dims", and Xdmf3ReaderS skips a
        !> DataItem with ItemType="HyperSlab" ("unrecognized array type").
        subroutine put_component(name, c, n, file)
            character(len=*), intent(in) :: name, n, file
            integer, intent(in) :: c

            character(len=:), allocatable :: component

            component = name//"_"//trim(voigt_components(c))
            call put('        <Attribute Name="'//component// &
                '" AttributeType="Scalar" Center="Node">')
            call put("          "//data_item(n, "Float", file//":/xdmf/"//component))
            call put("        </Attribute>")
        end subroutine put_component

    end subroutine write_xdmf

    !> A real with 17 significant digits (enough to read back the same double).
    pure function real_text(value) result(text)
        real(wp), intent(in) :: value
        character(len=:), allocatable :: text

        character(len=32) :: buffer

        write (buffer, "(es24.16e3)") value
        text = trim(adjustl(buffer))
    end function real_text

    !> Whether the index lists the particles of a part: parts without particles are left
    !> out, except the first one when no part has any (every time then has its particles).
    pure logical function listed(counts, part)
        integer(i8), intent(in) :: counts(:)
            !! number of particles of every part at one output time
        integer, intent(in) :: part
            !! part (image)

        listed = counts(part) > 0 .or. (part == 1 .and. all(counts == 0))
    end function listed

    !> An XDMF DataItem pointing to an HDF5 dataset.
    module pure function data_item(dims, number_type, source) result(text)
        character(len=*), intent(in) :: dims
            !! dimensions, slowest first ("n 3")
        character(len=*), intent(in) :: number_type
            !! "Float" (8 bytes) or "Int" (default integer)
        character(len=*), intent(in) :: source
            !! "file.h5:/group/dataset"
        character(len=:), allocatable :: text

        character(len=:), allocatable :: precision

        if (number_type == "Int") then
            precision = int_text(storage_size(0)/8)
        else
            precision = int_text(storage_size(0.0_wp)/8)
        end if
        text = '<DataItem Dimensions="'//dims//'" NumberType="'//number_type// &
            '" Precision="'//precision//'" Format="HDF">'//source//"</DataItem>"
    end function data_item

    !> Name of the particle file of output number `index` (0-based).
    module pure function particle_file_name(index) result(name)
        integer, intent(in) :: index
            !! output index
        character(len=:), allocatable :: name
            !! "particles_NNNNNN.h5"

        character(len=6) :: index_text

        write (index_text, "(i6.6)") index
        name = "particles_"//index_text//".h5"
    end function particle_file_name

    !> Name of the file of one image at output number `index` (0-based): the particle file
    !> itself for a single image, a part file for several.
    module pure function part_file_name(index, image, images) result(name)
        integer, intent(in) :: index
            !! output index
        integer, intent(in) :: image
            !! image, 1 .. images
        integer, intent(in) :: images
            !! number of images
        character(len=:), allocatable :: name
            !! "particles_NNNNNN.h5" (one image) or "particles_NNNNNN_pKKKKK.h5"

        character(len=6) :: index_text
        character(len=5) :: image_text

        if (images == 1) then
            name = particle_file_name(index)
            return
        end if
        write (index_text, "(i6.6)") index
        write (image_text, "(i5.5)") image
        name = "particles_"//index_text//"_p"//image_text//".h5"
    end function part_file_name

end submodule mpm_output_xdmf
